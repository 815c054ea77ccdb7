"""The mastermind fails safe: no weather information keeps the roof closed, stopping and dawn close
and park, an error in its loop closes and parks and the loop goes on (simulated observatory)."""

from __future__ import annotations

from collections.abc import Awaitable, Callable, Sequence
from datetime import UTC, datetime, timedelta

import pytest

from nightcrew.astro import sun_altitude
from nightcrew.clock import VirtualClock
from nightcrew.events import (
    GoodWeatherEvent,
    NewImageEvent,
    RoofOpenedEvent,
    TaskFailedEvent,
    TaskFinishedEvent,
    TaskStartedEvent,
)
from nightcrew.interfaces import IWeather, MotionStatus, SensorValue, WeatherReport, WeatherSensor
from nightcrew.robotic.archives import ScheduleStore
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import TaskState
from nightcrew.testing import SITE

from .mastermind_night import PLEIADES, Night, Parts, group, start_mastermind, start_night

ARCTURUS = {"name": "Arcturus", "ra": 213.915, "dec": 19.182}  # high in the south-east before dawn


async def _wait(
    night: Night, what: str, condition: Callable[[], Awaitable[bool]], clock_seconds: float
) -> float:
    """Clock seconds until ``await condition()`` holds; fails after ``clock_seconds``."""
    start = night.obs.clock.time()
    while not await condition():
        assert night.obs.clock.time() - start < clock_seconds, f"{what}: not within {clock_seconds} s"
        await night.obs.clock.sleep(2.0)
    return night.obs.clock.time() - start


async def test_without_weather_information_the_roof_stays_closed_then_stop_and_dawn_close_it(
    parts: Parts,
) -> None:
    obs, archive = parts
    obs.clock = archive.clock = VirtualClock("2024-01-16T05:45:00+00:00")
    # The Sun reaches -12° at 05:58. The mastermind starts a task only if its estimate ends before
    # that; a camera far slower than estimated (120 s read-outs, 2 s assumed) runs it into dawn.
    groups = [group(ARCTURUS, count=8, exposure_time=30.0)]
    night = await start_night(parts, groups, readout_time=120.0)
    (task,) = night.tasks
    now = obs.clock.now()
    await archive.write_schedule([PlannedSlot(task.id, now, now + timedelta(hours=1))], replace_from=now)
    mastermind = await start_mastermind(night, weather=None)
    rec = night.recorder

    # No weather module and no GoodWeatherEvent yet: unknown weather is bad weather.
    await obs.clock.sleep(60.0)
    assert rec.of(RoofOpenedEvent) == [] and await night.closed_and_parked()
    await rec.comm.send_event(GoodWeatherEvent())

    async def started(count: int) -> bool:
        return len(rec.of(TaskStartedEvent)) >= count

    async def failed(count: int) -> bool:
        return len(rec.of(TaskFailedEvent)) >= count and await night.closed_and_parked()

    await _wait(night, "task started", lambda: started(1), 120.0)
    await obs.clock.sleep(100.0)

    # The operator stops robotic mode: the task stops with what it did, the observatory closes.
    await mastermind.stop()
    assert not await mastermind.is_autonomous()
    print(f"\nstopped: closed and parked {await _wait(night, 'stop', lambda: failed(1), 60.0):.0f} s later")
    first = rec.of(TaskFailedEvent)[0].reason
    assert first.startswith("interrupted by robotic mode being stopped: ") and first.endswith(
        " of 8 exposures done"
    )

    # Started again, it resumes the task in its slot, until the Sun rises above -12°.
    await mastermind.start()
    await _wait(night, "task resumed", lambda: started(2), 120.0)
    await _wait(night, "dawn", lambda: failed(2), 1200.0)
    dawn = rec.of(TaskFailedEvent)[1]
    aborted_at = next(t for t, e in rec.events if e is dawn)
    sun = sun_altitude(SITE.latitude, SITE.longitude, aborted_at)
    print(f"dawn: aborted with the Sun at {sun:.2f}°: {dawn.reason}")
    assert -12.0 < sun < -11.8
    assert dawn.reason.startswith("interrupted by the Sun at -1") and "(the task needs ≤ -12°)" in dawn.reason
    assert await night.closed_and_parked()
    last_image = max(t for t, e in rec.events if isinstance(e, NewImageEvent))
    assert last_image <= aborted_at

    # Back in the pool, with the larger count of the two attempts; tomorrow is another night.
    stored = await archive.get_task(task.id)
    assert stored.state is TaskState.FAILED and stored.schedulable
    done = [int(r.split(": ")[1].split(" ")[0]) for r in (first, dawn.reason)]
    assert stored.status.progress.total_exposures == max(done) > 0


async def test_a_task_that_would_run_into_dawn_is_not_started_and_stays_in_the_pool(
    parts: Parts, caplog: pytest.LogCaptureFixture
) -> None:
    obs, archive = parts
    obs.clock = archive.clock = VirtualClock("2024-01-16T05:45:00+00:00")
    night = await start_night(parts, [group(ARCTURUS, count=40, exposure_time=30.0)])  # 24 min
    (task,) = night.tasks
    now = obs.clock.now()
    await archive.write_schedule([PlannedSlot(task.id, now, now + timedelta(hours=1))], replace_from=now)
    await start_mastermind(night, weather=GoodWeather())
    await obs.clock.sleep(300.0)
    assert "not starting task 1 (Arcturus in V) now: with 1428 s left it would end at 06:0" in caplog.text
    assert night.recorder.of(TaskStartedEvent) == [] and night.recorder.of(RoofOpenedEvent) == []
    assert await night.closed_and_parked()
    stored = await archive.get_task(task.id)
    assert stored.state is TaskState.SCHEDULED and stored.schedulable  # not failed: may fit later


class GoodWeather(IWeather):
    """A local weather verdict that is always good (so only the error can close the roof)."""

    async def is_weather_good(self) -> bool:
        return True

    async def get_current_weather(self) -> WeatherReport:
        return WeatherReport(time=datetime.now(UTC), good=True, sensors={})

    async def get_sensor_value(self, station: str, sensor: WeatherSensor) -> SensorValue:
        return SensorValue(time=datetime.now(UTC), value=None)


class FlakyStore(ScheduleStore):
    """A schedule store whose disk is gone while ``broken``."""

    def __init__(self, store: ScheduleStore) -> None:
        self._store, self.broken, self.failures = store, True, 0

    async def write_schedule(self, entries: Sequence[PlannedSlot], *, replace_from: datetime) -> None:
        await self._store.write_schedule(entries, replace_from=replace_from)

    async def read_schedule(
        self, *, start: datetime | None = None, end: datetime | None = None
    ) -> list[PlannedSlot]:
        if self.broken:
            self.failures += 1
            raise OSError("schedule disk gone")
        return await self._store.read_schedule(start=start, end=end)


async def test_an_error_in_the_loop_closes_and_parks_and_the_loop_goes_on(
    parts: Parts, caplog: pytest.LogCaptureFixture
) -> None:
    obs, archive = parts
    night = await start_night(parts, [group(PLEIADES, count=2, exposure_time=5.0)])
    (task,) = night.tasks
    now = obs.clock.now()
    await archive.write_schedule([PlannedSlot(task.id, now, now + timedelta(hours=1))], replace_from=now)
    await night.roof.open_roof()  # as a person (or an earlier crash) left it
    await night.telescope.init()
    store = FlakyStore(archive)
    await start_mastermind(night, weather=GoodWeather(), schedule=store)

    safe_after = await _wait(night, "safe", night.closed_and_parked, 60.0)
    print(f"\nclosed and parked {safe_after:.0f} s after an error")
    assert "error in the robotic loop (schedule disk gone); closing the roof and parking" in caplog.text
    assert await night.roof.get_motion_status() is MotionStatus.PARKED

    store.broken = False  # the loop was restarted with backoff and goes on

    async def finished() -> bool:
        return bool(night.recorder.of(TaskFinishedEvent))

    await _wait(night, "task finished", finished, 300.0)
    assert "background task robotic loop crashed; restarting in 1 s" in caplog.text
    assert (await archive.get_task(task.id)).state is TaskState.COMPLETED


async def test_a_task_left_running_by_a_killed_mastermind_is_failed_then_run_again(
    parts: Parts, caplog: pytest.LogCaptureFixture
) -> None:
    obs, archive = parts
    night = await start_night(parts, [group(PLEIADES, count=2, exposure_time=5.0)])
    (task,) = night.tasks
    now = obs.clock.now()
    await archive.write_schedule([PlannedSlot(task.id, now, now + timedelta(hours=1))], replace_from=now)
    await archive.mark_started(task.id)  # and then the process died
    await obs.clock.sleep(60.0)
    await start_mastermind(night, weather=GoodWeather())

    async def finished() -> bool:
        return bool(night.recorder.of(TaskFinishedEvent))

    await _wait(night, "task finished", finished, 300.0)
    assert "left running: interrupted by a restart of the mastermind: 0 of 2 exposures done" in caplog.text
    stored = await archive.get_task(task.id)
    assert stored.state is TaskState.COMPLETED and stored.status.progress.total_exposures == 2
    assert [e.id for e in night.recorder.of(TaskStartedEvent)] == [task.id]
