"""The meridian flip: when a frame needs one (pure), and a night segment on a simulated GEM where
the target crosses the meridian: one flip, frames on both sides, PIERSIDE right, no collision."""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator
from datetime import datetime
from typing import cast

import pytest

from nightcrew.astro import local_sidereal_time
from nightcrew.astro.pier import SIDEREAL_RATE, hour_angle
from nightcrew.errors import ConfigError
from nightcrew.images import Pipeline
from nightcrew.images.processors.offsets import NStarOffsets
from nightcrew.interfaces import PierSide
from nightcrew.modules.focus.series import AutoFocusSeries
from nightcrew.modules.pointing import AutoGuiding
from nightcrew.modules.sim import SimCamera, SimFocuser
from nightcrew.robotic.scripts import ImagingScript
from nightcrew.robotic.scripts._flip import FLIP_BEYOND_MERIDIAN, flip_wait
from nightcrew.testing import SITE, Observatory
from nightcrew.vfs import MemoryFile

from .runner_sim import DETECTOR, PLEIADES, ProgressLog, SimSetup, make_task, start_sim

DEC = 24.0
GEM_OPTIONS = {"gem": {"east": -120.0, "west": 120.0, "counterweight_up": 2.0}, "slew_rate": 4.0}


def test_a_frame_that_would_end_past_the_meridian_waits_for_it_then_flips() -> None:
    minute = 60.0 * SIDEREAL_RATE  # degrees of hour angle per minute
    beyond = FLIP_BEYOND_MERIDIAN / SIDEREAL_RATE  # seconds from the meridian to the flip
    assert flip_wait(-2 * minute, 60.0, PierSide.WEST, 0.0) is None  # ends before the meridian
    assert flip_wait(-0.5 * minute, 60.0, PierSide.WEST, 0.0) == pytest.approx(30.0 + beyond)  # wait, flip
    assert flip_wait(-0.5 * minute, 60.0, PierSide.WEST, 1.0) is None  # allowed 4 min past it
    assert flip_wait(3 * minute, 60.0, PierSide.WEST, 0.0) == 0.0  # past the meridian: flip now
    assert flip_wait(3 * minute, 60.0, PierSide.EAST, 0.0) is None  # already flipped
    assert flip_wait(3 * minute, 60.0, PierSide.UNKNOWN, 0.0) is None  # not a GEM


def test_a_flip_allowance_that_makes_no_sense_is_a_config_error() -> None:
    with pytest.raises(ConfigError, match=r"key 'flip_past_meridian': must be within 0..90 degrees, got 120"):
        ImagingScript(flip_past_meridian=120.0)


def _ra_at_hour_angle(gem: SimSetup, ha: float) -> float:
    """The ICRS right ascension at hour angle ``ha`` (dec :data:`DEC`) on the clock now."""
    now = gem.obs.clock.time()
    ra = (local_sidereal_time(now, SITE.longitude) - ha) % 360.0
    return (ra + hour_angle(ra, DEC, SITE.longitude, now) - ha) % 360.0


@pytest.fixture
async def gem() -> AsyncIterator[SimSetup]:
    obs = Observatory()
    try:
        yield await start_sim(obs, telescope_options=GEM_OPTIONS)
    finally:
        await obs.close()
        MemoryFile.clear_shared()


async def test_a_target_crossing_the_meridian_is_flipped_between_two_frames(gem: SimSetup) -> None:
    # A target 5 minutes east of the meridian: three 60 s frames before it, two after the flip.
    ra = _ra_at_hour_angle(gem, -5 * 60.0 * SIDEREAL_RATE)
    runner = await gem.runner({"EXPOSE": ImagingScript()})
    frames = {"exposure_time": 60.0, "exposure_count": 5, "optical_elements": {"filter": "V"}, "binning": 2}
    task = make_task(
        {"type": "EXPOSE", "target": {"name": "M45ish", "ra": ra, "dec": DEC}, "instrument_configs": [frames]}
    )
    await runner.run_task(task, ProgressLog())

    headers = await gem.headers(5)
    sides = [header["PIERSIDE"] for header in headers]
    assert sides[0] == "WEST" and sides[-1] == "EAST"
    assert sides == sorted(sides, reverse=True)  # one flip: WEST frames, then EAST frames
    for header in headers:  # each frame on the side where its target had the counterweight down
        start = datetime.fromisoformat(header["DATE-OBS"]).timestamp()
        end_ha = hour_angle(ra, DEC, SITE.longitude, start + header["EXPTIME"])
        assert (end_ha <= 0.0) == (header["PIERSIDE"] == "WEST"), (header["PIERSIDE"], end_ha)
    last_west = sides.index("EAST") - 1
    before = datetime.fromisoformat(headers[last_west]["DATE-OBS"]).timestamp() + 60.0
    after = datetime.fromisoformat(headers[last_west + 1]["DATE-OBS"]).timestamp()
    assert after - before >= 180.0 / 4.0  # the flip slewed the hour axis half round
    assert await gem.telescope.get_pier_collisions() == []
    assert await gem.telescope.get_pier_side() is PierSide.EAST


async def test_guiding_stops_for_the_flip_and_starts_again_after_it(
    gem: SimSetup, caplog: pytest.LogCaptureFixture
) -> None:
    await gem.obs.start(
        SimCamera, "guider", detector=DETECTOR, catalog_depth=14.0, seed=3, readout_time=0.2, weather=None
    )
    guiding = await gem.obs.start(
        AutoGuiding, "autoguider", camera="guider", pipeline=Pipeline([NStarOffsets()]), exposure_time=5.0
    )
    runner = await gem.runner({"EXPOSE": ImagingScript(autoguider="autoguider")})
    ra = _ra_at_hour_angle(gem, -3.5 * 60.0 * SIDEREAL_RATE)  # the third frame would cross it
    frames = {"exposure_time": 60.0, "exposure_count": 3, "optical_elements": {"filter": "V"}, "binning": 2}
    task = make_task(
        {
            "type": "EXPOSE",
            "target": {"name": "M45ish", "ra": ra, "dec": DEC},
            "guiding_config": {"mode": "ON", "optional": False},
            "instrument_configs": [frames],
        }
    )
    with caplog.at_level(logging.INFO):
        await runner.run_task(task, ProgressLog())
    messages = [record.getMessage() for record in caplog.records]
    started = [i for i, m in enumerate(messages) if "new reference frame (guiding started)" in m]
    flip = next(i for i, m in enumerate(messages) if "meridian flip for M45ish" in m)
    stopped = [i for i, m in enumerate(messages) if m == "autoguider: guiding stopped"]
    assert len(started) == 2 and started[0] < flip < started[1]  # started again after the flip
    assert any(flip < i < started[1] for i in stopped)  # and stopped for it
    headers = [await gem.read(filename) for filename in gem.frames]  # the guider's frames too
    science = [header["PIERSIDE"] for header in headers if header["IMAGETYP"] == "object"]
    assert science[0] == "WEST" and science[-1] == "EAST" and science == sorted(science, reverse=True)
    assert not await guiding.is_running()
    assert await gem.telescope.get_pier_collisions() == []


async def test_the_focus_is_found_again_after_the_flip_when_asked() -> None:
    # The Pleiades (rich enough for a focus series) reach the meridian at about 19:30 UTC.
    obs = Observatory(epoch="2024-01-15T19:20:00+00:00")
    try:
        gem = await start_sim(obs, telescope_options=GEM_OPTIONS)
        await obs.start(AutoFocusSeries, "focus", camera="camera", focuser="focuser")
        focuser = obs.module("focuser", SimFocuser)
        await focuser.set_focus(24.9)  # 0.1 mm off the best focus (25.0)
        refocus = {"focus": "focus", "count": 7, "step": 0.08, "exposure_time": 2.0}
        runner = await gem.runner({"EXPOSE": ImagingScript(refocus_after_flip=refocus)})
        ra, dec = cast(float, PLEIADES["ra"]), cast(float, PLEIADES["dec"])
        # On the west side, 20 s before the meridian: the 60 s frame would cross it.
        await gem.telescope.move_radec(ra, dec)
        assert await gem.telescope.get_pier_side() is PierSide.WEST
        await obs.clock.sleep(-(hour_angle(ra, dec, SITE.longitude, obs.clock.time()) + 0.08) / SIDEREAL_RATE)
        frames = {"exposure_time": 60.0, "exposure_count": 1, "optical_elements": {"filter": "V"}}
        await runner.run_task(
            make_task({"type": "EXPOSE", "target": PLEIADES, "instrument_configs": [frames]}), ProgressLog()
        )
        assert await focuser.get_focus() == pytest.approx(25.0, abs=0.03)
        (header,) = await gem.headers(1)  # the focus frames are not broadcast
        assert header["PIERSIDE"] == "EAST"
    finally:
        await obs.close()
        MemoryFile.clear_shared()


@pytest.mark.parametrize(
    ("refocus", "message"),
    [
        ({"count": 2}, r"key 'refocus_after_flip.count': count must be an integer >= 3, got 2"),
        ({"steps": 0.1}, r"key 'refocus_after_flip.steps': steps is not an option; known: count, "),
    ],
)
def test_refocus_options_that_make_no_sense_are_config_errors(
    refocus: dict[str, object], message: str
) -> None:
    with pytest.raises(ConfigError, match=message):
        ImagingScript(refocus_after_flip=refocus)
