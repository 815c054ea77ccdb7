"""A small simulated observatory whose camera sees the Pleiades, for the tests of camera-driven modules."""

from __future__ import annotations

from typing import Any

from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.modules.sim import (
    SimCamera,
    SimFilterWheel,
    SimFocuser,
    SimRoof,
    SimTelescope,
    SimWeatherStation,
)
from nightcrew.testing import Observatory

__all__ = ["CATALOG_DEPTH", "DETECTOR", "PLEIADES", "SEED", "expose", "start_observatory"]

PLEIADES = (56.75, 24.12)  # high in the sky at the conftest epoch
# A 1024² chip keeps each frame fast; 9 µm at 1600 mm is 1.16"/px, a 0.33° field.
DETECTOR = {"chip_width": 1024, "chip_height": 1024, "cosmic_rays_per_s": 0.0}
CATALOG_DEPTH = 15.0
SEED = 3


async def start_observatory(
    observatory: Observatory,
    *,
    weather: type[SimWeatherStation] = SimWeatherStation,
    camera_class: type[SimCamera] = SimCamera,
    target: tuple[float, float] = PLEIADES,
    **camera: Any,
) -> SimCamera:
    """Telescope tracking ``target`` (the Pleiades), focuser at best focus, V filter, roof open, clear sky."""
    telescope = await observatory.start(SimTelescope, "telescope", init_time=0.0, seed=1)
    await observatory.start(SimFocuser, "focuser", focus=25.0, best_focus=25.0)
    await observatory.start(SimFilterWheel, "filters", filters=["V", "R"], filter_name="V")
    roof = await observatory.start(SimRoof, "roof", open_time=1.0)
    await observatory.start(weather, "weather", scenario=[{"at": 0, "clouds": 0.0}])
    await telescope.init()
    await telescope.move_radec(*target)
    await roof.open_roof()
    options: dict[str, Any] = {
        "detector": DETECTOR,
        "catalog_depth": CATALOG_DEPTH,
        "seed": SEED,
        "filter_throughputs": {"V": 0.8, "R": 0.9},
        "readout_time": 0.5,
        **camera,
    }
    return await observatory.start(camera_class, "camera", **options)


async def expose(observatory: Observatory, camera: SimCamera, seconds: float = 1.0) -> fits.PrimaryHDU:
    await camera.set_exposure_time(seconds)
    filename = await camera.grab_data()
    return (await observatory.vfs.read_fits(filename))[0]
