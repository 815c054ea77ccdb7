"""A simulated night for the mastermind tests: devices, weather, archive, runner, a queue scheduler.

Real modules throughout (see test_mastermind_sim); only the scheduler is a stand-in.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from datetime import datetime, timedelta
from typing import Any

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
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.scripts import ImagingScript
from nightcrew.robotic.tasks import Task, TaskState, parse_request_group
from nightcrew.testing import Observatory
from nightcrew.weather import Boolean, Valid

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


def queue(tasks: list[Task], start: datetime, slot: timedelta) -> list[PlannedSlot]:
    return [PlannedSlot(t.id, start + i * slot, start + (i + 1) * slot) for i, t in enumerate(tasks)]


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
