"""The mastermind on the simulated observatory (LocalNetwork, fast clock): a night with rain and a dawn.

Real modules throughout: SimRoof, SimTelescope, SimCamera, a SimWeatherStation playing a scripted
scenario judged by the Weather module, the SQLite archive and the TaskRunner with the ImagingScript.
Only the scheduler is a stand-in (:class:`QueueScheduler`): it puts the schedulable tasks one after
another from the GoodWeatherEvent's eta on, which is enough to show that an interrupted task comes
back. Times are asserted in clock seconds.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from dataclasses import dataclass, field
from datetime import datetime, timedelta
from pathlib import Path
from typing import Any

import pytest

from nightcrew.events import (
    BadWeatherEvent,
    Event,
    GoodWeatherEvent,
    NewImageEvent,
    RoofClosedEvent,
    RoofClosingEvent,
    RoofOpenedEvent,
    TaskFailedEvent,
    TaskFinishedEvent,
    TaskStartedEvent,
)
from nightcrew.interfaces import IAutoFocus, ModuleState, MotionStatus
from nightcrew.modules import Module
from nightcrew.modules.robotic.mastermind import Mastermind
from nightcrew.modules.sim import (
    SimCamera,
    SimFilterWheel,
    SimFocuser,
    SimRoof,
    SimTelescope,
    SimWeatherStation,
)
from nightcrew.modules.weather import ModuleStation, Weather
from nightcrew.robotic.archives import ScheduleEntry, SqliteTaskArchive
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.scripts import ImagingScript
from nightcrew.robotic.tasks import Task, TaskState, parse_request_group
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile
from nightcrew.weather import Boolean, Valid

SPEED = 200.0
DETECTOR = {"chip_width": 128, "chip_height": 128, "cosmic_rays_per_s": 0.0}
PLEIADES = {"name": "Pleiades", "ra": 56.75, "dec": 24.12}
ORION = {"name": "M42", "ra": 83.82, "dec": -5.39}
HYADES = {"name": "Hyades", "ra": 66.75, "dec": 15.87}
EXPOSURES, EXPOSURE_TIME = 6, 20.0


class Recorder(Module, IAutoFocus):
    """Notes every event it hears with its clock time; also a stand-in autofocus that notes its runs."""

    TYPES: tuple[type[Event], ...] = (
        NewImageEvent,
        RoofOpenedEvent,
        RoofClosingEvent,
        RoofClosedEvent,
        TaskStartedEvent,
        TaskFinishedEvent,
        TaskFailedEvent,
        BadWeatherEvent,
        GoodWeatherEvent,
    )

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.events: list[tuple[float, Event]] = []
        self.focus_runs: list[float] = []

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        for event_type in self.TYPES:
            await self.comm.register_event(event_type, self.on_event)

    async def on_event(self, event: Event, sender: str) -> None:
        self.events.append((self.clock.time(), event))

    def times(self, event_type: type[Event]) -> list[float]:
        return [t for t, e in self.events if isinstance(e, event_type)]

    def of(self, event_type: type[Event]) -> list[Any]:
        return [e for _, e in self.events if isinstance(e, event_type)]

    async def auto_focus(self, count: int, step: float, exposure_time: float) -> tuple[float, float]:
        self.focus_runs.append(self.clock.time())
        await self.clock.sleep(20.0)
        return 25.0, 0.01

    async def auto_focus_status(self) -> dict[str, Any]:
        return {}

    async def abort(self) -> None:
        pass


class QueueScheduler(Module):
    """A stand-in scheduler: on good weather, the schedulable tasks one after another from the eta."""

    def __init__(self, *, archive: SqliteTaskArchive, slot: float, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._archive, self._slot = archive, timedelta(seconds=slot)
        self.plans = 0

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(GoodWeatherEvent, self.on_good_weather)

    async def on_good_weather(self, event: GoodWeatherEvent, sender: str) -> None:
        tasks = sorted(await self._archive.get_schedulable_tasks(), key=lambda t: int(t.id))
        if any(t.state is TaskState.FAILED for t in tasks):  # the first plan is the test's
            start = event.eta or self.clock.now()
            await self._archive.write_schedule(queue(tasks, start, self._slot), replace_from=start)
            self.plans += 1


def queue(tasks: list[Task], start: datetime, slot: timedelta) -> list[ScheduleEntry]:
    return [ScheduleEntry(t.id, start + i * slot, start + (i + 1) * slot) for i, t in enumerate(tasks)]


def group(
    target: dict[str, Any], count: int = EXPOSURES, exposure_time: float = EXPOSURE_TIME
) -> dict[str, Any]:
    return {
        "name": f"{target['name']} in V",
        "proposal": "tests",
        "requests": [
            {
                "location": {"telescope_class": "0m4"},
                "windows": [{"start": "2024-01-15T17:00:00Z", "end": "2024-01-16T07:00:00Z"}],
                "configurations": [
                    {
                        "type": "EXPOSE",
                        "target": target,
                        "instrument_configs": [
                            {
                                "exposure_time": exposure_time,
                                "exposure_count": count,
                                "optical_elements": {"filter": "V"},
                            }
                        ],
                    }
                ],
            }
        ],
    }


@dataclass
class Night:
    obs: Observatory
    archive: SqliteTaskArchive
    recorder: Recorder
    roof: SimRoof
    telescope: SimTelescope
    mastermind: Mastermind | None = None
    tasks: list[Task] = field(default_factory=list)

    def since(self, start: float, event_type: type[Event]) -> list[float]:
        return [t - start for t in self.recorder.times(event_type)]

    async def closed_and_parked(self) -> bool:
        roof, telescope = await self.roof.get_motion_status(), await self.telescope.get_motion_status()
        return roof is MotionStatus.PARKED and telescope is MotionStatus.PARKED

    async def headers(self) -> list[Any]:
        return [(await self.obs.vfs.read_fits(e.filename))[0].header for e in self.recorder.of(NewImageEvent)]


async def start_night(
    parts: Parts,
    groups: list[dict[str, Any]],
    scenario: list[dict[str, Any]] | None = None,
    *,
    readout_time: float = 1.0,
) -> Night:
    """The devices, the archive holding ``groups``, and with a ``scenario`` a weather station and Weather.

    ``readout_time``: the camera's, in seconds (the mastermind's duration estimate assumes 2 s).
    """
    obs, archive = parts
    recorder = await obs.start(Recorder, "recorder")
    tasks = [task for group in groups for task in await archive.add_request_group(parse_request_group(group))]
    telescope = await obs.start(SimTelescope, "telescope", init_time=5.0, settle_time=1.0, seed=1)
    await obs.start(SimFilterWheel, "filters", filters=["V", "R"], filter_name="V")
    await obs.start(SimFocuser, "focuser", focus=25.0, best_focus=25.0)
    roof = await obs.start(SimRoof, "roof", open_time=30.0, close_time=30.0)
    camera = {"detector": DETECTOR, "catalog_depth": 12.0, "seed": 3, "weather": None}
    camera["readout_time"] = readout_time
    await obs.start(SimCamera, "camera", roof="roof", **camera)
    if scenario is not None:
        await obs.start(SimWeatherStation, "weatherstation", interval=10.0, scenario=scenario)
        await obs.start(
            Weather,
            "weather",
            stations={"roof": ModuleStation(module="weatherstation")},
            checks={"roof.rain": Boolean(good_when=False), "roof.temperature": Valid(max_age=120)},
            interval=10.0,
            min_good_time=60.0,
        )
    return Night(obs, archive, recorder, roof, telescope, tasks=tasks)


async def start_mastermind(site: Night, **options: Any) -> Mastermind:
    runner = TaskRunner(scripts={"EXPOSE": ImagingScript(filters="filters")})
    options.setdefault("weather", "weather")
    site.mastermind = await site.obs.start(
        Mastermind,
        "mastermind",
        archive=site.archive,
        runner=runner,
        poll_interval=5.0,
        keep_open=600.0,
        **options,
    )
    return site.mastermind


Parts = tuple[Observatory, SqliteTaskArchive]


@pytest.fixture
async def parts(tmp_path: Path) -> AsyncIterator[Parts]:
    """A fast observatory and an open SQLite archive on its clock; closed in that order."""
    obs = Observatory(speed=SPEED)
    archive = SqliteTaskArchive(tmp_path / "tasks.sqlite", clock=obs.clock, poll_interval=0)
    await archive.open()
    try:
        yield obs, archive
    finally:
        await obs.close()
        await archive.close()
        MemoryFile.clear_shared()


RAIN_AT, DRY_AT = 660.0, 900.0  # task b runs from ~600 s to ~740 s


async def test_a_night_with_rain_runs_every_task_and_never_exposes_with_the_roof_closed(parts: Parts) -> None:
    scenario = [
        {"at": 0, "temperature": 8.0},
        {"at": RAIN_AT - 10, "temperature": 8.0},
        {"at": RAIN_AT, "rain": True, "temperature": 3.0},
        {"at": DRY_AT, "rain": False},
    ]
    site = await start_night(parts, [group(PLEIADES), group(ORION), group(HYADES)], scenario)
    observatory = site.obs
    t0 = observatory.clock.time()
    now = observatory.clock.now()
    await observatory.start(QueueScheduler, "scheduler", archive=site.archive, slot=600.0)
    a, b, c = site.tasks
    await site.archive.write_schedule(
        [
            ScheduleEntry(a.id, now, now + timedelta(seconds=600)),
            ScheduleEntry(b.id, now + timedelta(seconds=600), now + timedelta(seconds=1200)),
            ScheduleEntry(c.id, now + timedelta(seconds=1200), now + timedelta(seconds=1800)),
        ],
        replace_from=now,
    )
    mastermind = await start_mastermind(site, autofocus="recorder", refocus_temperature_change=2.0)
    assert await mastermind.is_autonomous()

    async def all_completed() -> bool:
        return all([(await site.archive.get_task(t.id)).state is TaskState.COMPLETED for t in site.tasks])

    done = False
    while not done:
        assert observatory.clock.time() - t0 < 3600, "the tasks did not complete"
        await observatory.clock.sleep(20.0)
        done = await all_completed() and await site.closed_and_parked()
    rec = site.recorder

    # Started and ended in order: a, b (interrupted), b again, c.
    started = [e.id for e in rec.of(TaskStartedEvent)]
    assert started == [a.id, b.id, b.id, c.id]
    ended = [
        (type(e).__name__, e.id) for _, e in rec.events if isinstance(e, TaskFinishedEvent | TaskFailedEvent)
    ]
    assert ended == [
        ("TaskFinishedEvent", a.id),
        ("TaskFailedEvent", b.id),
        ("TaskFinishedEvent", b.id),
        ("TaskFinishedEvent", c.id),
    ]

    # Rain: the task stopped within seconds, the roof was closed within a minute.
    (bad,) = site.since(t0, BadWeatherEvent)
    (failed,) = site.since(t0, TaskFailedEvent)
    closed_after = next(t - bad for t in site.since(t0, RoofClosedEvent) if t > bad)
    print(
        f"\nbad weather at {bad:.0f} s: aborted {failed - bad:.1f} s, roof closed {closed_after:.1f} s later"
    )
    assert RAIN_AT <= bad <= RAIN_AT + 25
    assert failed - bad <= 10.0
    assert closed_after <= 60.0
    (failed_event,) = rec.of(TaskFailedEvent)
    assert failed_event.reason.startswith("interrupted by bad weather: ") and failed_event.reason.endswith(
        f" of {EXPOSURES} exposures done"
    )
    assert failed_event.retryable  # so the scheduler plans it again
    reason = failed_event.reason

    # Every image: the task's cards, exposed entirely while the roof was open. The retry of b took
    # only the frames the rain had kept it from taking.
    headers = await site.headers()
    assert 0 < int(reason.split(": ")[1].split(" ")[0]) < EXPOSURES
    assert len(headers) == 3 * EXPOSURES
    ids = [h["TASK-ID"] for h in headers]
    assert ids == sorted(ids, key=[a.id, b.id, c.id].index) and set(ids) == {a.id, b.id, c.id}
    assert all(h["PROPOSAL"] == "tests" and h["TASK-NAM"].endswith(" in V") for h in headers)
    open_intervals = _open_intervals(rec)
    for header in headers:
        begin = datetime.fromisoformat(header["DATE-OBS"]).replace(tzinfo=now.tzinfo).timestamp()
        end = begin + header["EXPTIME"]
        assert any(opened <= begin and end <= closing + 1.0 for opened, closing in open_intervals), header[
            "DATE-OBS"
        ]
    spans = [(round(o - t0), round(c - t0)) for o, c in open_intervals]
    print(f"{len(headers)} images, none exposed while the roof was closed; open from/to (s): {spans}")

    # Focus: before the first task, and again after the rain had cooled the air by 5 °C.
    focus = [t - t0 for t in rec.focus_runs]
    assert len(focus) == 2 and focus[1] > DRY_AT, focus

    # The archive: all completed, b with its exposures, the last thing: closed and parked.
    assert await site.closed_and_parked()
    tasks = [await site.archive.get_task(t.id) for t in site.tasks]
    assert [t.status.progress.total_exposures for t in tasks] == [EXPOSURES] * 3


def _open_intervals(rec: Recorder) -> list[tuple[float, float]]:
    """(roof opened, roof started closing) clock times."""
    opened = rec.times(RoofOpenedEvent)
    closing = rec.times(RoofClosingEvent)
    return [(o, next((c for c in closing if c > o), float("inf"))) for o in opened]
