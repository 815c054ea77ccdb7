"""A short robotic sequence on Alpaca devices only (alpaca-simulators): open the dome, slew, a focus
series with the Alpaca camera and focuser (the existing AutoFocusSeries module), three exposures in
two filters, close, park; astrometry.net's solve-field solves a frame near the commanded position.

Needs Debian ``astrometry.net`` + ``astrometry-data-tycho2``: skipped without solve-field, except
under CI=true, where that is a failure.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from astropy.wcs import WCS  # type: ignore[import-untyped]

from nightcrew.astro import altaz_to_radec
from nightcrew.clock import RealClock
from nightcrew.images import Image
from nightcrew.images.astrometry import SolveField, SolveHints
from nightcrew.interfaces import (
    IAutoFocus,
    ICamera,
    IExposureTime,
    IFilters,
    IRoof,
    ITelescope,
    MotionStatus,
)
from nightcrew.modules.alpaca import (
    AlpacaCamera,
    AlpacaDome,
    AlpacaFilterWheel,
    AlpacaFocuser,
    AlpacaTelescope,
)
from nightcrew.modules.focus.series import AutoFocusSeries, ProjectionFocusMeasure
from nightcrew.sim.catalog_data import load_reference_stars, unit_vectors
from nightcrew.testing import ContractProbe, Observatory
from nightcrew.testing.alpaca import SIMULATOR_SITE, TEST_OVERRIDES, AlpacaSimulator, merge_config

from ..sim.solving import offset_arcsec, solve_field_executable

pytestmark = pytest.mark.solver

#: 5 µm pixels at 400 mm: 2.6"/pixel over a 2048-pixel chip (1.5°), enough Tycho-2 stars to solve
#: and fine enough to see the simulator's defocus; a small aperture keeps the G < 10 stars of the
#: offline table below saturation in the 2 s focus frames.
FOCAL_LENGTH_MM, PIXEL_UM, CHIP = 400.0, 5.0, 2048
PIXEL_SCALE = 206.265 * PIXEL_UM / FOCAL_LENGTH_MM
SEQUENCE_OVERRIDES: dict[str, Any] = merge_config(
    TEST_OVERRIDES,
    {
        "devices": {
            "telescope": {0: {"focallength": FOCAL_LENGTH_MM / 1000.0, "aperturediameter": 0.015}},
            "camera": {
                0: {
                    "pixelsizex": PIXEL_UM,
                    "pixelsizey": PIXEL_UM,
                    "cameraxsize": CHIP,
                    "cameraysize": CHIP,
                    "numx": CHIP,
                    "numy": CHIP,
                }
            },
        }
    },
)


def star_rich_field(unix_time: float) -> tuple[float, float]:
    """(ra, dec) of the high field (altitude 45..75°) with the most catalogue stars now: the sky
    at test time decides what is up, and a field poor in G < 10 stars would not solve."""
    stars = load_reference_stars()
    xyz = unit_vectors(stars.ra, stars.dec)
    best: tuple[int, float, float] = (-1, 0.0, 0.0)
    for alt in (45.0, 60.0, 75.0):
        for az in range(0, 360, 20):
            ra, dec = altaz_to_radec(
                alt, float(az), SIMULATOR_SITE.latitude, SIMULATOR_SITE.longitude, unix_time
            )
            centre = unit_vectors(np.array([float(ra) % 360.0]), np.array([float(dec)]))[0]
            count = int(np.count_nonzero(xyz @ centre > np.cos(np.radians(0.6))))
            best = max(best, (count, float(ra) % 360.0, float(dec)))
    return best[1], best[2]


#: alpaca-simulators' best focus: step 10000 at 1 µm per step.
TRUE_FOCUS_MM = 10.0


async def test_a_night_on_alpaca_devices_only(start_alpaca_simulator: Callable[..., AlpacaSimulator]) -> None:
    executable = solve_field_executable()
    simulator = start_alpaca_simulator(overrides=SEQUENCE_OVERRIDES)
    server = {"server": simulator.url}
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        robot = await obs.start(ContractProbe, "robot")  # drives everything through proxies
        await obs.start(AlpacaDome, "dome", **server)
        await obs.start(AlpacaTelescope, "telescope", **server)
        await obs.start(AlpacaCamera, "camera", **server)
        focuser = await obs.start(AlpacaFocuser, "focuser", **server)
        await focuser.set_focus(TRUE_FOCUS_MM + 0.1)  # start a little off
        await obs.start(AlpacaFilterWheel, "filters", **server)
        await obs.start(
            AutoFocusSeries, "focus", camera="camera", focuser="focuser", measure=ProjectionFocusMeasure()
        )
        dome = await robot.comm.proxy("dome", IRoof)
        telescope = await robot.comm.proxy("telescope", ITelescope)
        camera = await robot.comm.proxy("camera", ICamera)
        filters = await robot.comm.proxy("filters", IFilters)
        focus = await robot.comm.proxy("focus", IAutoFocus)

        await dome.open_roof()
        await telescope.init()
        ra, dec = star_rich_field(obs.clock.time())
        await telescope.move_radec(ra, dec)

        best, error = await focus.auto_focus(5, 0.1, 2.0)
        assert best == pytest.approx(TRUE_FOCUS_MM, abs=0.05), f"best focus {best} ± {error} mm"

        await (await robot.comm.proxy("camera", IExposureTime)).set_exposure_time(2.0)
        files: list[str] = []
        for filter_name, count in (("Red", 2), ("Blue", 1)):
            await filters.set_filter(filter_name)
            for _ in range(count):
                files.append(await camera.grab_data())
        images = [await Image.from_vfs(obs.vfs, f) for f in files]
        assert [image.header["FILTER"] for image in images] == ["Red", "Red", "Blue"]
        for image in images:
            assert image.data.shape == (CHIP, CHIP)
            assert image.header["FOCUS"] == pytest.approx(best, abs=0.002)
            assert float(image.header["RA"]) == pytest.approx(ra, abs=0.01)

        await dome.close_roof()
        await telescope.park()
        assert await telescope.get_motion_status() is MotionStatus.PARKED
        assert await dome.get_motion_status() is MotionStatus.PARKED

    solver = SolveField(executable=executable, cpu_limit_s=120.0, timeout_s=600.0)
    hints = SolveHints(
        ra_deg=ra, dec_deg=dec, radius_deg=2.0, pixel_scale_arcsec=PIXEL_SCALE, scale_tolerance=0.2
    )
    frame = images[-1]
    wcs = WCS(await solver.solve_image(frame.data, hints=hints))
    offset = offset_arcsec(wcs, frame.data.shape, ra, dec)
    assert offset < 120.0, f"solved {offset:.1f} arcsec from the commanded position"
