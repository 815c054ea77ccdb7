"""A night that survives device faults: a device failing under a task costs at most the frame in
flight. The mastermind waits for a device module that went away and restarts the task from its
progress; a device that stays away fails the task as a device fault (retried later, the roof stays
open); a task's own error is no device fault. Real modules on the in-process comm, virtual clock."""

from __future__ import annotations

from datetime import timedelta

import pytest

from nightcrew.errors import (
    ConfigError,
    DeviceBusyError,
    ForbiddenError,
    GrabImageError,
    InvalidArgumentError,
    ModuleError,
    NotSupportedError,
    RemoteError,
    RemoteTimeoutError,
)
from nightcrew.events import (
    NewImageEvent,
    RoofClosingEvent,
    TaskFailedEvent,
    TaskFinishedEvent,
    TaskStartedEvent,
)
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.sim import SimCamera
from nightcrew.robotic.mastermind import DeviceFault, device_fault
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.runner import ScriptError
from nightcrew.robotic.tasks import Task, TaskState

from .mastermind_night import (
    DETECTOR,
    EXPOSURE_TIME,
    EXPOSURES,
    ORION,
    PLEIADES,
    Night,
    Parts,
    group,
    start_mastermind,
    start_night,
)

DRY = [{"at": 0, "temperature": 8.0}]
CAMERA = {"detector": DETECTOR, "catalog_depth": 12.0, "seed": 3, "weather": None, "readout_time": 1.0}


def _wrapped(error: Exception) -> ScriptError:
    """``error`` as a script reports it (ScriptError raised from it)."""
    try:
        raise ScriptError(f"take frame failed: {error}") from error
    except ScriptError as wrapped:
        return wrapped


@pytest.mark.parametrize(
    ("error", "fault"),
    [
        (RemoteError("module 'camera' is not online"), DeviceFault(None, "module 'camera' is not online")),
        (RemoteTimeoutError("grab_data() did not finish within 70 s", module="camera"), "camera"),
        (ModuleError("module is in error state: lost camera 0", module="camera"), "camera"),
        (DeviceBusyError("Camera is not idle", module="camera"), "camera"),
        (GrabImageError("exposure failed", module="camera"), "camera"),
        (InvalidArgumentError("unknown filter 'B'", module="filters"), None),
        (NotSupportedError("no script configured for SPECTRUM configurations"), None),
        (ConfigError("bad", key="x"), None),
        (ForbiddenError("mastermind may not call camera.grab_data()", module="camera"), None),
        (ScriptError("sky flats incomplete: 3 of 9 missing (twilight over?)"), None),
    ],
)
def test_a_device_failure_is_told_from_the_tasks_own(
    error: Exception, fault: DeviceFault | str | None
) -> None:
    for raised in (error, _wrapped(error)):
        found = device_fault(raised)
        if isinstance(fault, str):
            assert found is not None and found.module == fault and found.reason == str(error)
        else:
            assert found == fault


async def _run_for_an_hour(night: Night) -> Task:
    """Schedule the night's one task from now for an hour and start the mastermind."""
    (task,) = night.tasks
    now = night.obs.clock.now()
    await night.archive.write_schedule(
        [PlannedSlot(task.id, now, now + timedelta(hours=1))], replace_from=now
    )
    await start_mastermind(night, device_wait=60.0)
    return task


async def _camera_away(night: Night, images: int, clock_seconds: float) -> float:
    """Close the camera module after ``images`` frames, start a new one ``clock_seconds`` later;
    returns the clock time it went away."""
    obs = night.obs
    await obs.wait_for(lambda: len(night.recorder.of(NewImageEvent)) >= images, 600.0, interval=1.0)
    gone = obs.clock.time()
    # As a kill: the module is offline, and the call it was serving fails.
    camera = obs.module("camera", SimCamera)
    await camera.close()
    await camera.abort()
    await obs.clock.sleep(clock_seconds)
    await obs.start(SimCamera, "camera", roof="roof", **CAMERA)  # as the supervisor's restart
    return gone


async def test_a_camera_module_that_restarts_mid_task_costs_at_most_the_frame_in_flight(parts: Parts) -> None:
    night = await start_night(parts, [group(PLEIADES)], DRY)
    obs, archive, task = night.obs, night.archive, await _run_for_an_hour(night)

    await _camera_away(night, 2, 20.0)
    await obs.wait_for(
        lambda: night.recorder.of(TaskFinishedEvent) != [], 1800.0, interval=2.0, message="task finished"
    )
    rec = night.recorder
    assert rec.of(TaskFailedEvent) == [] and len(rec.of(TaskStartedEvent)) == 1
    assert (
        rec.times(RoofClosingEvent) == []
        or min(rec.times(RoofClosingEvent)) >= rec.times(TaskFinishedEvent)[0]
    )
    stored = await archive.get_task(task.id)
    assert stored.state is TaskState.COMPLETED and stored.status.progress.total_exposures == EXPOSURES
    assert len(rec.of(NewImageEvent)) == EXPOSURES  # the frame in flight was lost, no other
    # The restarted task set the new camera up again (a fresh module knows nothing of it).
    assert {h["EXPTIME"] for h in await night.headers()} == {EXPOSURE_TIME}


async def test_a_device_that_stays_away_fails_the_task_as_a_device_fault_and_the_night_goes_on(
    parts: Parts,
) -> None:
    night = await start_night(parts, [group(PLEIADES), group(ORION)], DRY)
    obs, archive, (first, second) = night.obs, night.archive, night.tasks
    now = obs.clock.now()
    await archive.write_schedule(
        [
            PlannedSlot(first.id, now, now + timedelta(minutes=10)),
            PlannedSlot(second.id, now + timedelta(minutes=10), now + timedelta(minutes=20)),
        ],
        replace_from=now,
    )
    await start_mastermind(night, device_wait=60.0)

    gone = await _camera_away(night, 2, 150.0)
    rec = night.recorder
    await obs.wait_for(lambda: rec.of(TaskFinishedEvent) != [], 1800.0, interval=2.0, message="second task")
    (failed,) = rec.of(TaskFailedEvent)
    failed_at = next(t for t, e in rec.events if e is failed)
    into_task = gone - rec.times(TaskStartedEvent)[0]
    print(f"\ncamera away {into_task:.0f} s into the task; the task failed {failed_at - gone:.0f} s later")
    assert failed.id == first.id and failed.retryable and failed.device_fault
    assert "camera" in failed.reason
    assert 60.0 <= failed_at - gone <= 60.0 + 30.0  # the device_wait, plus the frame in flight
    assert [e.id for e in rec.of(TaskFinishedEvent)] == [second.id]
    finished = rec.times(TaskFinishedEvent)[0]
    assert all(t >= finished for t in rec.times(RoofClosingEvent))  # open all along until then
    stored = await archive.get_task(first.id)
    assert (
        stored.state is TaskState.FAILED
        and stored.schedulable
        and stored.status.progress.total_exposures >= 2
    )


async def test_a_tasks_own_error_is_no_device_fault(parts: Parts) -> None:
    unknown_binning = group(PLEIADES)
    unknown_binning["requests"][0]["configurations"][0]["instrument_configs"][0]["binning"] = 5
    night = await start_night(parts, [unknown_binning], DRY)
    obs = night.obs
    await _run_for_an_hour(night)
    await obs.wait_for(lambda: night.recorder.of(TaskFailedEvent) != [], 600.0, interval=2.0)
    (failed,) = night.recorder.of(TaskFailedEvent)
    assert not failed.retryable and not failed.device_fault
    assert "binning 5x5 is not supported" in failed.reason
    assert len(night.recorder.of(TaskStartedEvent)) == 1  # not restarted


async def test_a_task_due_while_a_device_module_restarts_waits_for_it(parts: Parts) -> None:
    night = await start_night(parts, [group(PLEIADES)], DRY)
    obs, archive, task = night.obs, night.archive, await _run_for_an_hour(night)

    async def opening() -> bool:
        return await night.roof.get_motion_status() is not MotionStatus.PARKED

    await obs.wait_for(opening, 600.0, interval=1.0, message="roof opening")
    await obs.module("camera", SimCamera).close()  # away when the task is due (roof: 30 s to open)
    await obs.clock.sleep(50.0)
    await obs.start(SimCamera, "camera", roof="roof", **CAMERA)

    await obs.wait_for(lambda: night.recorder.of(TaskFinishedEvent) != [], 1800.0, interval=2.0)
    assert night.recorder.of(TaskFailedEvent) == []
    assert (await archive.get_task(task.id)).state is TaskState.COMPLETED


async def test_a_camera_module_restarted_between_two_calls_is_set_up_again(parts: Parts) -> None:
    night = await start_night(parts, [group(PLEIADES)], DRY)
    obs, archive, task = night.obs, night.archive, await _run_for_an_hour(night)
    await obs.wait_for(lambda: len(night.recorder.of(NewImageEvent)) >= 2, 600.0, interval=1.0)
    # The old module goes without failing a call; the new one starts with a 1-s exposure time.
    await obs.module("camera", SimCamera).close()
    await obs.start(SimCamera, "camera", roof="roof", **CAMERA)

    await obs.wait_for(lambda: night.recorder.of(TaskFinishedEvent) != [], 1800.0, interval=2.0)
    assert night.recorder.of(TaskFailedEvent) == []
    stored = await archive.get_task(task.id)
    assert stored.state is TaskState.COMPLETED and stored.status.progress.total_exposures == EXPOSURES
    assert {h["EXPTIME"] for h in await night.headers()} == {EXPOSURE_TIME}
