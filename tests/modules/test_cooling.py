"""A cooled night on virtual time: the schedule cools the simulated camera before dusk, holds it,
flags frames off the set point and warms up at dawn."""

from __future__ import annotations

import itertools
import logging
import shutil
from datetime import UTC, datetime
from pathlib import Path

import pytest

from nightcrew.astro import sun_crossing
from nightcrew.cli.main import main
from nightcrew.errors import ConfigError
from nightcrew.modules.camera import BaseCamera
from nightcrew.modules.camera.cooling import CoolingSchedule
from nightcrew.modules.sim import SimCamera
from nightcrew.night.build import bundled_observatory
from nightcrew.testing import Observatory
from nightcrew.testing.observatory import SITE

from .devices import GradientCamera

#: An afternoon in January: the schedule has to start cooling by itself.
AFTERNOON = "2024-01-15T14:00:00+00:00"
NO_DEVICES = {"telescope": None, "focuser": None, "filters": None, "roof": None, "weather": None}


async def cooled_camera(obs: Observatory, **cooler: float) -> tuple[SimCamera, CoolingSchedule]:
    camera = await obs.start(
        SimCamera,
        "camera",
        detector={"chip_width": 64, "chip_height": 64, "cosmic_rays_per_s": 0.0},
        cooler={"ambient": 8.0, "max_delta": 35.0, "time_constant": 60.0, **cooler},
        readout_time=0.5,
        **NO_DEVICES,
    )
    schedule = await obs.start(
        CoolingSchedule, "cooling", camera="camera", setpoint=-10.0, ramp_rate=2.0, interval=120.0
    )
    return camera, schedule


async def dark_header(obs: Observatory, camera: SimCamera) -> dict[str, object]:
    await camera.set_exposure_time(1.0)
    filename = await camera.grab_data(image_type="dark")  # type: ignore[arg-type]
    return dict((await obs.vfs.read_fits(filename))[0].header)


async def test_cooled_down_before_dusk_held_flagged_and_warmed_up_at_dawn(
    caplog: pytest.LogCaptureFixture,
) -> None:
    caplog.set_level(logging.INFO)
    async with Observatory(epoch=AFTERNOON) as obs:
        camera, _ = await cooled_camera(obs)
        dusk = sun_crossing(SITE, obs.clock.time(), -3.0, rising=False)
        samples: list[tuple[float, bool, float, float]] = []  # time, on, set point, chip
        while obs.clock.time() < dusk:
            status = await camera.get_cooling()
            assert status.temperature is not None
            samples.append((obs.clock.time(), status.enabled, status.setpoint, status.temperature))
            await obs.clock.sleep(60.0)
        on = [s for s in samples if s[1]]
        assert on and not samples[0][1], "cooling began by itself in the afternoon"
        # The ramp-rate limit: a set point moves at most 2 °C per minute since the schedule's last
        # look (every 120 s; the samples here are not aligned with those looks).
        for (t0, _, set0, _), (t1, _, set1, _) in itertools.pairwise(on):
            assert abs(set1 - set0) <= 2.0 / 60.0 * (t1 - t0 + 120.0) + 1e-9
        ramp_end = next(s[0] for s in on if s[2] == -10.0)
        assert ramp_end - on[0][0] >= (8.0 + 10.0) / 2.0 * 60.0 - 120.0  # 18 °C took 9 minutes
        at_set_point = next(s[0] for s in on if abs(s[3] + 10.0) <= 0.5)
        # Cold well before dusk: the lead time (600 s) covers the chip's lag behind the set point.
        assert at_set_point <= dusk - 300.0
        header = await dark_header(obs, camera)
        assert header["SET-TEMP"] == -10.0
        assert header["CCD-TEMP"] == pytest.approx(-10.0, abs=0.5)
        assert 0.0 < header["COOLPOW"] < 100.0  # type: ignore[operator]
        assert header["TEMP-OK"] is True

        # Dawn: the cooler ramps up and goes off.
        dawn = sun_crossing(SITE, obs.clock.time(), -3.0, rising=True)
        await obs.clock.sleep(dawn - obs.clock.time() + 1800.0)
        status = await camera.get_cooling()
        assert not status.enabled
        assert status.temperature is not None and status.temperature > 5.0
    assert "cooling down from" in caplog.text and "cooler off" in caplog.text


async def test_a_set_point_out_of_reach_warns_and_its_frames_are_flagged(
    caplog: pytest.LogCaptureFixture,
) -> None:
    async with Observatory(epoch=datetime(2024, 1, 15, 22, tzinfo=UTC)) as obs:
        camera = await obs.start(
            SimCamera,
            "camera",
            detector={"chip_width": 64, "chip_height": 64},
            cooler={"ambient": 8.0, "max_delta": 10.0},
            **NO_DEVICES,
        )
        await camera.set_cooling(True, -10.0)
        assert "below what the cooler can reach (-2 °C" in caplog.text
        await obs.clock.sleep(1800.0)
        status = await camera.get_cooling()
        assert status.power == 100.0
        header = await dark_header(obs, camera)
        assert header["CCD-TEMP"] == pytest.approx(-2.0, abs=0.01)
        assert header["TEMP-OK"] is False


async def test_a_schedule_without_a_site_or_with_a_bad_rate_is_refused() -> None:
    async with Observatory(site=None) as obs:
        with pytest.raises(ConfigError, match="site"):
            await obs.start(CoolingSchedule, "cooling")
    with pytest.raises(ConfigError, match="ramp_rate must be > 0"):
        CoolingSchedule(name="cooling", ramp_rate=-1.0)


@pytest.mark.usefixtures("bundled_xmpp_files")
def test_check_refuses_a_set_point_below_the_cameras_reach(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    observatory = tmp_path / "observatory"
    ignore = shutil.ignore_patterns("frames", "xmpp", "logs", "*.sqlite*", "*.jsonl")
    shutil.copytree(bundled_observatory(), observatory, ignore=ignore)
    cooling = observatory / "robotic" / "cooling.yaml"
    assert main(["check", str(cooling), str(observatory / "camera.yaml")]) == 0, capsys.readouterr().err
    text = cooling.read_text(encoding="utf-8")
    cooling.write_text(text.replace("setpoint: -10 ", "setpoint: -40 "), encoding="utf-8")
    capsys.readouterr()
    assert main(["check", str(observatory)]) == 2  # as docs/observatory.md, "Cooling", runs it
    error = capsys.readouterr().err
    assert "cooling.yaml: key 'setpoint': -40 °C is below the -27 °C the camera of" in error


class UncooledCamera(GradientCamera):
    """The gradient camera without its cooler (the base camera's refusal)."""

    _hw_set_cooling = BaseCamera._hw_set_cooling


async def test_a_camera_without_a_cooler_is_told_once(
    observatory: Observatory, caplog: pytest.LogCaptureFixture
) -> None:
    await observatory.start(UncooledCamera, "camera")
    await observatory.start(CoolingSchedule, "cooling")
    await observatory.clock.sleep(600.0)
    assert caplog.text.count("the camera cannot cool") == 1
