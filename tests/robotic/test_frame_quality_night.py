"""A simulated stretch of night with dithering, grading and refocus triggers in the imaging script:
dithered frames where the headers say they were taken, a bad frame taken again, a refocus after
the star images grew (a focuser that slipped between two tasks)."""

from __future__ import annotations

import itertools
import logging
from collections.abc import AsyncIterator

import pytest

from nightcrew.astro import angular_separation
from nightcrew.images import Pipeline
from nightcrew.images.processors.offsets import NStarOffsets
from nightcrew.modules.focus.series import AutoFocusSeries
from nightcrew.modules.pointing import AutoGuiding
from nightcrew.modules.sim import SimCamera, SimFocuser
from nightcrew.robotic.scripts import ImagingScript
from nightcrew.robotic.tasks import Task
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile

from .runner_sim import DETECTOR, PLEIADES, ProgressLog, SimSetup, make_task, start_sim

GRADING = {"min_history": 3, "max_retakes": 2}
REFOCUS = {"fwhm_rise": 0.3, "focus": "focus", "count": 7, "step": 0.08, "exposure_time": 2.0}


@pytest.fixture
async def night() -> AsyncIterator[SimSetup]:
    # The Pleiades high in the evening: rich enough for a focus series.
    obs = Observatory(epoch="2024-01-15T19:20:00+00:00")
    try:
        setup = await start_sim(obs)
        await obs.start(AutoFocusSeries, "focus", camera="camera", focuser="focuser")
        await obs.start(
            SimCamera, "guider", detector=DETECTOR, catalog_depth=14.0, seed=3, readout_time=0.2, weather=None
        )
        guiding = Pipeline([NStarOffsets()])
        await obs.start(AutoGuiding, "autoguider", camera="guider", pipeline=guiding, exposure_time=10.0)
        yield setup
    finally:
        await obs.close()
        MemoryFile.clear_shared()


def _task(count: int, name: str, dither: dict[str, object] | None = None) -> Task:
    frames = {"exposure_time": 10.0, "exposure_count": count, "optical_elements": {"filter": "V"}}
    configuration: dict[str, object] = {"type": "EXPOSE", "target": PLEIADES, "instrument_configs": [frames]}
    if dither is not None:
        configuration["dither_config"] = dither
        configuration["guiding_config"] = {"mode": "ON", "optional": False}
    return make_task(configuration, task_id=name)


async def test_dithered_graded_frames_and_a_refocus_when_the_stars_grow(
    night: SimSetup, caplog: pytest.LogCaptureFixture
) -> None:
    runner = await night.runner(
        {"EXPOSE": ImagingScript(grading=GRADING, refocus_triggers=REFOCUS, autoguider="autoguider")}
    )
    with caplog.at_level(logging.INFO):
        await runner.run_task(_task(3, "sharp"), ProgressLog())  # the night's medians
        focuser = night.obs.module("focuser", SimFocuser)
        await focuser.set_focus(25.15)  # the focuser slipped: stars ~4" wider
        progress = ProgressLog()
        dither = {"pattern": "SPIRAL", "amplitude": 20, "every": 1}
        await runner.run_task(_task(3, "dithered", dither), progress)
    messages = [record.getMessage() for record in caplog.records]
    assert sum("refocusing: FWHM" in m for m in messages) == 1  # the FWHM rise, not the retakes alone
    assert await focuser.get_focus() == pytest.approx(25.0, abs=0.03)
    assert sum(" again (retake " in m for m in messages) == 2
    assert progress.last.exposures_done == ((3,),)  # the failed frames did not count

    # 3 sharp frames, 2 out of focus (taken again), 3 dithered after the refocus; positions as the
    # frames' headers give them (the telescope's RA/DEC, offsets included).
    headers = await night.headers(3 + 2 + 3)
    positions = [(h["RA"], h["DEC"]) for h in headers[3:]]
    # The guider's corrections (a few tenths of an arcsec to ~1") move the frames a little too.
    retakes = [angular_separation(*positions[0], *p) * 3600.0 for p in positions[1:3]]
    assert max(retakes) < 2.0  # the retakes were taken where the frame was due, not dithered
    steps = [angular_separation(*a, *b) * 3600.0 for a, b in itertools.pairwise(positions[2:])]
    assert steps == [pytest.approx(20.0, abs=1.0)] * 2  # the spiral: 20" east, then 20" north
    assert (positions[4][1] - positions[3][1]) * 3600.0 == pytest.approx(20.0, abs=1.0)
    assert abs(positions[3][1] - positions[2][1]) * 3600.0 < 1.0  # the first step: east only

    # The guider was stopped for each dither and took its reference on the new position.
    started = [i for i, m in enumerate(messages) if "new reference frame (guiding started)" in m]
    dithers = [i for i, m in enumerate(messages) if m.startswith("dither ")]
    assert len(dithers) == 2 and len(started) == 3  # guiding started with the task and after each dither
    assert started[0] < dithers[0] < started[1] < dithers[1] < started[2]


async def test_each_filter_brings_its_focus_offset(night: SimSetup) -> None:
    offsets = {"V": 0.0, "R": 0.1}
    runner = await night.runner({"EXPOSE": ImagingScript(focuser="focuser", filter_focus_offsets=offsets)})
    frames = [{"exposure_time": 1.0, "optical_elements": {"filter": name}, "binning": 2} for name in "VRV"]
    task = make_task({"type": "EXPOSE", "target": PLEIADES, "instrument_configs": frames})
    await runner.run_task(task, ProgressLog())
    headers = await night.headers(3)
    assert [(h["FILTER"], h["FOCOFFS"]) for h in headers] == [("V", 0.0), ("R", 0.1), ("V", 0.0)]
