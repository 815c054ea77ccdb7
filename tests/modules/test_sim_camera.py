"""SimCamera in a small simulated observatory: everything it learns comes through the comm."""

from __future__ import annotations

import logging
from datetime import datetime
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import sep  # type: ignore[import-not-found]

from nightcrew.errors import ConfigError
from nightcrew.modules.camera import ExposureSettings, Frame
from nightcrew.modules.sim import (
    SimCamera,
    SimFocuser,
    SimRoof,
    SimWeatherStation,
)
from nightcrew.modules.sim.scene import Scene
from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.projection import FrameGeometry, Pointing, sky_to_pixel
from nightcrew.testing import Observatory

from .sim_observatory import CATALOG_DEPTH, DETECTOR, PLEIADES, SEED, expose, start_observatory

#: Clock seconds the slow weather station below takes to answer.
SLOW_ANSWER_S = 5.0


def detect(data: npt.NDArray[Any]) -> tuple[Any, float]:
    image = data.astype(np.float64)
    background = sep.Background(image)
    image -= background
    return sep.extract(image, 5.0, err=background.globalrms, minarea=5), float(background.globalrms)


async def test_exposure_has_full_headers_and_the_catalog_stars(observatory: Observatory) -> None:
    camera = await start_observatory(observatory)
    hdu = await expose(observatory, camera, 1.0)
    header = hdu.header
    for key in ("DATE-OBS", "EXPTIME", "IMAGETYP", "FILTER", "RA", "DEC", "AIRMASS", "FOCUS", "GAIN"):
        assert key in header, key
    assert header["EXPTIME"] == 1.0
    assert header["FILTER"] == "V"
    assert header["FOCUS"] == pytest.approx(25.0)
    assert (header["RA"], header["DEC"]) == pytest.approx(PLEIADES, abs=1e-6)  # commanded pointing
    assert header["SITELAT"] == pytest.approx(51.56)
    assert "CTYPE1" not in header  # no WCS: that is the solver's job
    assert hdu.data.shape == (1024, 1024)

    # Project the catalog with the true pointing: the brightest unsaturated stars must be found there.
    truth = Pointing(header["SIM-RA"], header["SIM-DEC"])
    geometry = FrameGeometry(1024, 1024, header["PIXSCALE"])
    stars = StarCatalog(depth=CATALOG_DEPTH, seed=SEED).query(*PLEIADES, 0.5, epoch=2024.04)
    x, y = sky_to_pixel(stars["ra"], stars["dec"], truth, geometry)
    inside = (x > 20) & (x < 1003) & (y > 20) & (y < 1003) & (stars["mag"] > 9.0) & (stars["mag"] < 12.0)
    x, y, mag = x[inside], y[inside], stars["mag"][inside]
    objects, _ = detect(hdu.data)
    assert len(objects) >= 20
    distance = np.hypot(objects["x"][None, :] - x[:, None], objects["y"][None, :] - y[:, None])
    nearest = distance.argmin(axis=1)
    found = distance[np.arange(len(x)), nearest] < 1.5
    assert found.mean() > 0.9, f"{found.sum()} of {len(x)} catalog stars found"

    # Brightness: instrumental magnitudes follow catalog magnitudes with one zero point.
    image = hdu.data.astype(np.float64) - sep.Background(hdu.data.astype(np.float64))
    flux, _, _ = sep.sum_circle(image, x[found], y[found], 8.0)
    electrons = flux * header["GAIN"]
    zero_points = mag[found] + 2.5 * np.log10(electrons / header["EXPTIME"])
    # Zero point 21.5, V throughput 0.8, extinction 0.2 mag per airmass, a few % lost outside r=8 px.
    expected = 21.5 + 2.5 * np.log10(0.8) - 0.2 * header["AIRMASS"]
    assert np.median(zero_points) == pytest.approx(expected, abs=0.15)
    assert np.std(zero_points) < 0.1


async def test_closed_roof_shows_no_stars(observatory: Observatory) -> None:
    camera = await start_observatory(observatory)
    roof = await observatory.start(SimRoof, "dome-roof", open_time=1.0)  # closed, named below
    await camera.close()
    camera = await observatory.start(SimCamera, "camera2", roof="dome-roof", detector=DETECTOR, seed=SEED)
    assert await roof.get_motion_status() == "parked"
    hdu = await expose(observatory, camera, 1.0)
    objects, _ = detect(hdu.data)
    assert len(objects) == 0
    assert hdu.header["SIM-RA"] == pytest.approx(PLEIADES[0], abs=0.1)  # it looked, but saw nothing


async def test_defocus_widens_the_stars(observatory: Observatory) -> None:
    camera = await start_observatory(observatory)
    sharp = await expose(observatory, camera, 1.0)
    focuser = observatory.module("focuser", SimFocuser)
    await focuser.set_focus(25.3)  # 0.3 mm off: 30"/mm * 0.3 = 9" of defocus blur
    blurred = await expose(observatory, camera, 1.0)
    assert blurred.header["FOCUS"] == pytest.approx(25.3)
    assert blurred.header["SIM-FWHM"] > 4 * sharp.header["SIM-FWHM"]
    measured = []
    for hdu in (sharp, blurred):
        objects, rms = detect(hdu.data)
        # Well-exposed, unsaturated stars; FWHM from their second moments.
        good = (objects["peak"] > 20 * rms) & (objects["peak"] < 30000)
        fwhm = 2.3548 * np.sqrt((objects["a"][good] ** 2 + objects["b"][good] ** 2) / 2.0)
        measured.append(float(np.median(fwhm)) * hdu.header["PIXSCALE"])
    # Moments of an undersampled Moffat read somewhat wide; the truth is in SIM-FWHM.
    assert 0.7 < measured[0] / sharp.header["SIM-FWHM"] < 1.6
    assert measured[1] > 3 * measured[0]


async def test_missing_peers_give_defaults_and_one_warning(
    observatory: Observatory, caplog: pytest.LogCaptureFixture
) -> None:
    camera = await observatory.start(SimCamera, "camera", detector=DETECTOR, seed=SEED)
    with caplog.at_level(logging.WARNING):
        hdu = await expose(observatory, camera, 1.0)
        await expose(observatory, camera, 1.0)
    warned = [r.getMessage() for r in caplog.records if "no answer from the" in r.getMessage()]
    assert sorted(m.split("no answer from the ")[1].split()[0] for m in warned) == [
        "filters",
        "focuser",
        "roof",
        "telescope",
        "weather",
    ]
    objects, _ = detect(hdu.data)
    assert len(objects) == 0  # no telescope: no light
    assert "SIM-RA" not in hdu.header


async def test_exposure_takes_clock_time_and_a_bias_takes_none(observatory: Observatory) -> None:
    camera = await start_observatory(observatory, readout_time=2.0)
    start = observatory.clock.time()
    await expose(observatory, camera, 30.0)
    assert observatory.clock.time() - start >= 32.0
    bias = await camera.grab_data(image_type="bias")  # type: ignore[arg-type]
    header = (await observatory.vfs.read_fits(bias))[0].header
    assert header["EXPTIME"] == 0.0


class SlowWeatherStation(SimWeatherStation):
    """The simulated weather station behind a slow link: each answer takes clock seconds."""

    async def get_cloud_cover(self) -> float:
        await self.clock.sleep(SLOW_ANSWER_S)
        return await super().get_cloud_cover()


class RenderLoggingCamera(SimCamera):
    """The simulated camera, noting the clock time each frame is rendered from (its shutter opening)."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.render_starts: list[float] = []

    def _blocking_render(
        self, scene: Scene, settings: ExposureSettings, start: float, rng: np.random.Generator
    ) -> Frame:
        self.render_starts.append(start)
        return super()._blocking_render(scene, settings, start, rng)


async def test_date_obs_is_when_the_shutter_opens_not_when_the_devices_were_asked(
    observatory: Observatory,
) -> None:
    camera = await start_observatory(
        observatory, weather=SlowWeatherStation, camera_class=RenderLoggingCamera
    )
    assert isinstance(camera, RenderLoggingCamera)
    called = observatory.clock.time()
    header = (await expose(observatory, camera, 10.0)).header
    (opened,) = camera.render_starts
    assert opened >= called + SLOW_ANSWER_S  # the camera waited for the weather before opening
    date_obs = datetime.fromisoformat(header["DATE-OBS"] + "+00:00").timestamp()
    assert opened - 0.001 < date_obs <= opened + 1e-6  # written to the millisecond, cut off
    assert (header["MJD-OBS"] - 40587.0) * 86400.0 == pytest.approx(opened, abs=0.001)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"detector": {"chip_widht": 100}}, r"detector.chip_widht.*unknown key; known keys: chip_width"),
        ({"detector": {"chip_width": 10.5}}, r"detector.chip_width.*whole number"),
        ({"optics": {"focal_length_mm": 0}}, r"optics.focal_length_mm.*must be > 0"),
        ({"filter_throughputs": {"V": 1.5}}, r"filter_throughputs.V.*within 0..1"),
        ({"catalog_depth": 30.0}, r"catalog_depth.*depth must be within"),
    ],
)
def test_bad_configuration_names_the_key(options: dict[str, Any], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        SimCamera(name="camera", **options)
