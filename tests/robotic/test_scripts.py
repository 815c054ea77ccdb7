"""The scripts on the simulated observatory: repeat timing, calibrations, focus, aborts, failures."""

from __future__ import annotations

import asyncio
from datetime import UTC, datetime

import pytest

from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.images import Pipeline
from nightcrew.images.processors.offsets import NStarOffsets
from nightcrew.interfaces import ExposureStatus, MotionStatus
from nightcrew.modules.focus.series import AutoFocusSeries
from nightcrew.modules.pointing import AutoGuiding
from nightcrew.modules.sim import SimCamera, SimFocuser
from nightcrew.robotic.runner import (
    ProgressCallback,
    ProgressReporter,
    Script,
    ScriptError,
    the_configuration,
)
from nightcrew.robotic.scripts import AutoFocusScript, CalibrationScript, ImagingScript, focus_step
from nightcrew.robotic.scripts._repeat import RepeatTiming
from nightcrew.robotic.tasks import InstrumentConfig, Task

from .runner_sim import DETECTOR, PLEIADES, ProgressLog, SimSetup, make_task, sim

__all__ = ["sim"]


def frames(count: int, exposure_time: float, filter_name: str = "V") -> dict[str, object]:
    return {
        "exposure_time": exposure_time,
        "exposure_count": count,
        "optical_elements": {"filter": filter_name},
        "binning": 2,
    }


# --- pure parts ------------------------------------------------------------------------------------


def test_repeat_timing_starts_only_exposures_that_end_in_time() -> None:
    timing = RepeatTiming(start=100.0, duration=30.0)
    assert timing.fits(125.0, 5.0)
    timing.record(started=100.0, ended=102.5, exposure_time=2.0)  # 0.5 s read-out learnt
    assert not timing.fits(125.0, 5.0)
    assert timing.fits(124.5, 5.0)


def test_focus_step_from_step_or_range_or_default() -> None:
    assert (
        focus_step(InstrumentConfig(exposure_time=1, exposure_count=9, extra_params={"step": 0.1}), 0.05)
        == 0.1
    )
    span = InstrumentConfig(exposure_time=1, exposure_count=9, extra_params={"focus_range": 2.0})
    assert focus_step(span, 0.05) == pytest.approx(0.25)
    assert focus_step(InstrumentConfig(exposure_time=1, exposure_count=9), 0.05) == 0.05
    with pytest.raises(InvalidArgumentError, match="positive number of mm, got 'wide'"):
        focus_step(InstrumentConfig(exposure_time=1, extra_params={"step": "wide"}), 0.05)


# --- on the simulation -----------------------------------------------------------------------------


async def test_repeat_expose_cycles_until_the_repeat_duration_is_used_up(sim: SimSetup) -> None:
    runner = await sim.runner({"REPEAT_EXPOSE": ImagingScript()})
    task = make_task(
        {
            "type": "REPEAT_EXPOSE",
            "target": PLEIADES,
            "repeat_duration": 60.0,
            "instrument_configs": [frames(1, 2.0, "V"), frames(1, 1.0, "R")],
        }
    )
    progress = ProgressLog(sim.obs.clock)
    await runner.run_task(task, progress)

    v, r = progress.last.exposures_done[0]
    # A cycle is 3 s of exposure plus two read-outs (1 s), filter changes and frame writing: about
    # 10 s of clock time on the virtual clock, whatever the machine's load.
    assert v + r >= 10
    assert v - r in (0, 1)  # whole cycles, perhaps one V frame more
    headers = await sim.headers(v + r)
    assert [h["FILTER"] for h in headers][:4] == ["V", "R", "V", "R"]
    # The repetitions start with the first frame; the last ends within the duration, and the
    # script stopped only because the next frame (<= 2 s plus its ~4 s overhead) would not fit.
    started = datetime.fromisoformat(headers[0]["DATE-OBS"]).replace(tzinfo=UTC).timestamp()
    assert 60.0 - 6.0 < progress.times[-1] - started <= 60.0


async def test_bias_and_dark_frames_without_moving_the_telescope(sim: SimSetup) -> None:
    calibration = CalibrationScript()
    runner = await sim.runner({"BIAS": calibration, "DARK": calibration})
    task = make_task(
        {"type": "BIAS", "instrument_configs": [{"exposure_time": 0, "exposure_count": 2, "binning": 2}]},
        {"type": "DARK", "instrument_configs": [{"exposure_time": 3.0, "exposure_count": 1, "binning": 2}]},
    )
    assert await runner.can_run(task)
    progress = ProgressLog()
    await runner.run_task(task, progress)

    headers = await sim.headers(3)
    assert [(h["IMAGETYP"], h["EXPTIME"]) for h in headers] == [("bias", 0.0), ("bias", 0.0), ("dark", 3.0)]
    assert [p.exposures_done for p in progress.reports] == [((1,), (0,)), ((2,), (0,)), ((2,), (1,))]
    assert await sim.telescope.get_motion_status() is MotionStatus.IDLE  # never slewed


async def test_auto_focus_then_expose_in_one_task(sim: SimSetup) -> None:
    await sim.obs.start(AutoFocusSeries, "focus", camera="camera", focuser="focuser")
    focuser = sim.obs.module("focuser", SimFocuser)
    await focuser.set_focus(24.9)  # 0.1 mm off the best focus (25.0)
    runner = await sim.runner({"AUTO_FOCUS": AutoFocusScript(), "EXPOSE": ImagingScript()})
    focus_frames = {"exposure_time": 2.0, "exposure_count": 7, "optical_elements": {"filter": "V"}}
    task = make_task(
        {
            "type": "AUTO_FOCUS",
            "target": PLEIADES,
            "instrument_configs": [{**focus_frames, "extra_params": {"focus_range": 0.5}}],  # 25.0 inside
        },
        {"type": "EXPOSE", "target": PLEIADES, "instrument_configs": [frames(2, 1.0, "R")]},
    )
    assert await runner.can_run(task)
    progress = ProgressLog()
    await runner.run_task(task, progress)

    assert await focuser.get_focus() == pytest.approx(25.0, abs=0.02)
    assert [p.exposures_done for p in progress.reports] == [((7,), (0,)), ((7,), (1,)), ((7,), (2,))]
    headers = await sim.headers(2)  # the focus frames are not broadcast
    assert [(h["FILTER"], h["IMAGETYP"]) for h in headers] == [("R", "object"), ("R", "object")]
    assert headers[0]["FOCUS"] == pytest.approx(25.0, abs=0.02)


async def test_abort_mid_task_stops_the_exposure_keeps_the_frame_and_stops_guiding(sim: SimSetup) -> None:
    await sim.obs.start(
        SimCamera, "guider", detector=DETECTOR, catalog_depth=14.0, seed=3, readout_time=0.2, weather=None
    )
    guiding = await sim.obs.start(
        AutoGuiding, "autoguider", camera="guider", pipeline=Pipeline([NStarOffsets()]), exposure_time=1.0
    )
    runner = await sim.runner({"EXPOSE": ImagingScript(autoguider="autoguider")})
    task = make_task(
        {
            "type": "EXPOSE",
            "target": PLEIADES,
            "guiding_config": {"mode": "ON", "optional": False},
            "instrument_configs": [frames(3, 20.0)],
        }
    )
    assert await runner.can_run(task)
    progress = ProgressLog()
    running = asyncio.create_task(runner.run_task(task, progress))

    async def second_frame_exposing() -> bool:
        return bool(progress.reports) and await sim.camera.get_exposure_status() is ExposureStatus.EXPOSING

    await sim.obs.wait_for(second_frame_exposing, 300.0, interval=0.1, message="second frame")
    assert await guiding.is_running()
    running.cancel()
    with pytest.raises(asyncio.CancelledError):
        await running

    assert await sim.camera.get_exposure_status() is ExposureStatus.IDLE
    assert not await guiding.is_running()
    # The science frame was stopped, read out and kept, saying so; it is not counted as done, but
    # the progress records it with the seconds its header gives.
    assert progress.last.exposures_done == ((1,),)
    whole, cut = await sim.headers(2)
    assert "CUTSHORT" not in whole and whole["EXPTIME"] == 20.0
    assert cut["CUTSHORT"] is True and cut["EXPREQ"] == 20.0 and 0.0 <= cut["EXPTIME"] < 20.0
    (kept,) = progress.last.cut_short
    assert (kept.configuration, kept.instrument_config) == (0, 0)
    assert kept.exposed == pytest.approx(cut["EXPTIME"], abs=1e-6)


async def test_a_failing_step_fails_the_task_and_says_why(sim: SimSetup) -> None:
    runner = await sim.runner({"EXPOSE": ImagingScript()})
    south = {"name": "Deep South", "ra": 56.75, "dec": -70.0}  # never rises at 51.6° N
    task = make_task({"type": "EXPOSE", "target": south, "instrument_configs": [frames(1, 1.0)]})
    with pytest.raises(ScriptError, match=r"slew to Deep South failed: MoveError: .*altitude"):
        await runner.run_task(task, ProgressLog())
    assert sim.frames == []


async def test_optional_guiding_may_fail_required_guiding_may_not(sim: SimSetup) -> None:
    runner = await sim.runner({"EXPOSE": ImagingScript(autoguider="no-such-guider")})
    guided = {"type": "EXPOSE", "target": PLEIADES, "instrument_configs": [frames(1, 1.0)]}
    optional = make_task({**guided, "guiding_config": {"mode": "ON", "optional": True}})
    assert await runner.can_run(optional)
    progress = ProgressLog()
    await runner.run_task(optional, progress)
    assert progress.last.total_exposures == 1

    required = make_task({**guided, "guiding_config": {"mode": "ON", "optional": False}})
    assert not await runner.can_run(required)
    with pytest.raises(
        ScriptError, match=r"start guiding failed: RemoteError: module 'no-such-guider' is not online"
    ):
        await runner.run_task(required, ProgressLog())


async def test_a_filter_the_wheel_lacks_cannot_run(sim: SimSetup) -> None:
    runner = await sim.runner({"EXPOSE": ImagingScript()})
    task = make_task({"type": "EXPOSE", "target": PLEIADES, "instrument_configs": [frames(1, 1.0, "Halpha")]})
    assert not await runner.can_run(task)


class GreetingScript(Script):
    """A SCRIPT configuration's script: remembers what it was asked to run."""

    def __init__(self) -> None:
        super().__init__()
        self.ran: list[str] = []

    async def can_run(self, task: Task) -> bool:
        return True

    async def run(self, task: Task, progress: ProgressCallback) -> None:
        config = the_configuration(task)
        self.ran.append(f"{config.extra_params['script']} at {self.clock.now():%H:%M}")
        reporter = ProgressReporter(task, progress)
        for index in range(len(config.instrument_configs)):
            await reporter.add(index)


async def test_script_configurations_go_to_the_script_named_in_extra_params(sim: SimSetup) -> None:
    greeting = GreetingScript()
    runner = await sim.runner({"SCRIPT:greet": greeting, "EXPOSE": ImagingScript()})
    task = make_task(
        {
            "type": "SCRIPT",
            "extra_params": {"script": "greet", "duration": 60},
            "instrument_configs": [frames(1, 1.0)],
        },
        {"type": "EXPOSE", "target": PLEIADES, "instrument_configs": [frames(1, 1.0)]},
    )
    assert runner.script_for(task) is greeting
    progress = ProgressLog()
    await runner.run_task(task, progress)
    assert greeting.ran == ["greet at 22:00"]  # with the runner's clock (the conftest epoch)
    assert [p.exposures_done for p in progress.reports] == [((1,), (0,)), ((1,), (1,))]

    other = make_task({"type": "SCRIPT", "extra_params": {"script": "dance", "duration": 60}})
    with pytest.raises(NotSupportedError, match="no script configured for SCRIPT:dance configurations"):
        await runner.run_task(other, ProgressLog())
