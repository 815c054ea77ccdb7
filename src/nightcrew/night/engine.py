"""A whole robotic night on the simulated observatory, in one process.

The devices (the top-level files of the bundled observatory) and the robotic modules (its
``robotic/`` directory: weather verdict, scheduler, mastermind with runner and scripts, focus
series, flat fields, acquisition, guiding, seeing, cooling, recorder) are built on one in-process
network and one clock (virtual in ``nightcrew sim``). The task archive is a fresh SQLite file in
``out_dir`` loaded with the bundled sample tasks and a low-priority survey that fills the night;
the scheduler plans from it and the mastermind runs what it planned. Nobody drives the night:
this function only watches (progress, the scheduler's plans into the recorder) until the clock
reaches ``end`` or ``stop`` is set, then stops the mastermind, parks the telescope and closes the
roof - also after an error - and closes every module.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass
from datetime import date, datetime
from pathlib import Path
from typing import Any, TypeVar

from nightcrew.astro import sun_altitude
from nightcrew.clock import Clock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.errors import ConfigError
from nightcrew.events import NewImageEvent, TaskFailedEvent, TaskFinishedEvent, TaskStartedEvent
from nightcrew.interfaces import IRoboticScheduler, IStartStop, Plan
from nightcrew.modules import Module
from nightcrew.modules.robotic import Mastermind, SchedulerModule
from nightcrew.night.build import (
    DATA_VARIABLE,
    FRAMES,
    SIM_RPC_GRACE,
    build_observatory,
    data_environ,
    images_vfs,
    options_directory,
    park_and_close,
)
from nightcrew.night.plan import one_window_each, samples_for_night, survey_groups
from nightcrew.night.recorder import NIGHT_RECORD, SCHEDULE_RECORD, EventRecorder
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.samples import load_samples
from nightcrew.robotic.tasks import RequestGroup
from nightcrew.site import Site

__all__ = ["EVENTS_FILE", "FRAMES", "NightProgress", "WholeNight", "night_tasks", "run_whole_night"]

log = logging.getLogger(__name__)

#: The recorder's file in the output directory.
EVENTS_FILE = "events.jsonl"
#: The task archive in the output directory (robotic/scheduler.yaml and mastermind.yaml name it).
TASKS_FILE = "tasks.sqlite"
#: Clock seconds between two looks of the watcher (progress line, new plans into the record).
_WATCH_INTERVAL_S = 30.0
#: Where the robotic modules' files are, below the observatory's directory.
ROBOTIC = "robotic"


@dataclass
class NightProgress:
    """What the progress line shows."""

    now: datetime
    sun_altitude: float
    task: str | None
    frames: int
    fraction: float  # of the night's clock time


@dataclass
class WholeNight:
    """How a night went: tasks started, whether it ran to its end (its frames: the files it wrote,
    :func:`nightcrew.report.describe_frames`; focus and acquisition frames are not announced)."""

    tasks_started: int = 0
    completed: bool = False


ProgressCallback = Callable[[NightProgress], None]
M = TypeVar("M", bound=Module)


async def run_whole_night(
    directory: Path,
    *,
    night: date,
    site: Site,
    clock: Clock,
    end: datetime,
    out_dir: Path,
    device_overrides: dict[str, dict[str, Any]],
    robotic_overrides: dict[str, dict[str, Any]] | None = None,
    seed: int | None = None,
    tasks: Sequence[RequestGroup] | None = None,
    progress: ProgressCallback | None = None,
    stop: asyncio.Event | None = None,
    extras: Collection[str] = (),
    environ: Mapping[str, str] | None = None,
) -> WholeNight:
    """Run the robotic night of ``directory`` until the clock shows ``end`` (see the module doc).

    ``tasks`` replaces the night's task list (default: the samples and the survey), e.g. with the
    short list of ``--quick``.

    ``extras`` names module files of :func:`~nightcrew.night.build.options_directory` to add (an
    IndiServer, the web console, the pipeline: what options of ``nightcrew sim`` ask for), opened
    after the others and closed before them; ``environ`` adds to the variables the files read.
    """
    await asyncio.to_thread(_blocking_clear_records, out_dir)
    network = LocalNetwork(rpc_grace=SIM_RPC_GRACE)
    # The watcher opens first, so that whatever fails later, it can still park and close.
    watcher = _Watcher(LocalComm("night", network=network), clock, site)
    if tasks is None:
        tasks = night_tasks(night, site)
    # The scheduler and the mastermind open the archive their files name in $OBSERVATORY_DATA.
    await _fill_archive(out_dir / TASKS_FILE, clock, tasks)
    vfs = images_vfs(out_dir / FRAMES)  # the modules share it; closed here, after them
    opened: list[Module] = []
    result = WholeNight()
    try:
        common: dict[str, Any] = {
            "clock": clock,
            "vfs": vfs,
            "seed": seed,
            "network": network,
            "environ": {**data_environ(out_dir), **(environ or {})},
        }
        modules = [
            *build_observatory(directory, overrides=device_overrides, **common),
            *build_observatory(directory / ROBOTIC, overrides=robotic_overrides, **common),
            *(build_observatory(options_directory(directory), names=extras, **common) if extras else []),
        ]
        recorder, scheduler = _the(modules, EventRecorder), _the(modules, SchedulerModule).name
        _check_archives(modules, out_dir / TASKS_FILE)
        for module in [watcher, *modules]:
            await module.open()
            opened.append(module)
        where = {"latitude": site.latitude, "longitude": site.longitude, "elevation": site.elevation}
        recorder.record(
            NIGHT_RECORD, {"site": where, "start": clock.now().isoformat(), "end": end.isoformat()}
        )
        result.completed = await watcher.watch(end, recorder, scheduler, progress, stop or asyncio.Event())
    finally:
        await _stop_safely(watcher, opened)
        result.tasks_started = watcher.tasks_started
        await vfs.close()
    return result


def night_tasks(night: date, site: Site) -> list[RequestGroup]:
    """The night's default task list: the samples (one window each) and the survey."""
    samples = samples_for_night(load_samples(), night, site)
    return [*(part for group in samples for part in one_window_each(group)), *survey_groups(night)]


def _the(modules: list[Module], kind: type[M]) -> M:
    """The one module of ``kind`` the night needs."""
    found = [m for m in modules if isinstance(m, kind)]
    if len(found) != 1:
        raise ConfigError(
            f"the robotic night needs exactly one {kind.__name__} in {ROBOTIC}/, found {len(found)}"
        )
    return found[0]


def _check_archives(modules: list[Module], filled: Path) -> None:
    """ConfigError unless the scheduler and the mastermind name the archive the night filled: an
    observatory directory whose files name another would run an empty night (or someone's tasks)."""
    for module in modules:
        if isinstance(module, SchedulerModule | Mastermind):
            archive = module.task_archive
            path = archive.path if isinstance(archive, SqliteTaskArchive) else None
            if path is None or path.resolve() != filled.resolve():
                raise ConfigError(
                    f"the {module.name}'s task archive is {path or type(archive).__name__}, not the night's "
                    f"{filled}: name it as {ROBOTIC}/{module.name}.yaml of the bundled observatory does "
                    f"(path: ${{{DATA_VARIABLE}}}/{TASKS_FILE})"
                )


def _blocking_clear_records(out_dir: Path) -> None:
    """Make ``out_dir``; remove the records and frames of an earlier night there."""
    (out_dir / FRAMES).mkdir(parents=True, exist_ok=True)
    for old in [*out_dir.glob(TASKS_FILE + "*"), out_dir / EVENTS_FILE, *(out_dir / FRAMES).glob("*.fits")]:
        old.unlink(missing_ok=True)


async def _fill_archive(path: Path, clock: Clock, tasks: Sequence[RequestGroup]) -> None:
    """A new archive at ``path`` holding ``tasks`` (as ``nightcrew tasks add`` would store them)."""
    archive = SqliteTaskArchive(path, clock=clock, poll_interval=0)
    await archive.open()
    try:
        for group in tasks:
            await archive.add_request_group(group)
    finally:
        await archive.close()


async def _stop_safely(watcher: Module, opened: list[Module]) -> None:
    """Stop the mastermind, park and close (errors logged), then close every module."""
    if watcher in opened:
        try:
            await (await watcher.proxy("mastermind", IStartStop)).stop()
        except Exception as exc:  # the safe shutdown below matters more
            log.error("could not stop the mastermind: %s", exc)
        try:
            await park_and_close(watcher)
        except Exception:
            log.exception("parking the telescope and closing the roof failed")
    for module in reversed(opened):
        try:
            await module.close()
        except Exception:
            log.exception("closing %s failed", module.name)


class _Watcher(Module):
    """Listens to the night (frames, tasks) and shows it; drives nothing."""

    def __init__(self, comm: LocalComm, clock: Clock, site: Site) -> None:
        super().__init__(comm=comm, clock=clock)
        self._where = site
        self.frames = 0  # announced (NewImageEvent): the progress line's live count
        self.tasks_started = 0
        self.task: str | None = None

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)
        await self.comm.register_event(TaskStartedEvent, self.on_task_started)
        await self.comm.register_event(TaskFinishedEvent, self.on_task_ended)
        await self.comm.register_event(TaskFailedEvent, self.on_task_ended)

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        self.frames += 1

    async def on_task_started(self, event: TaskStartedEvent, sender: str) -> None:
        self.tasks_started += 1
        self.task = event.name

    async def on_task_ended(self, event: TaskFinishedEvent | TaskFailedEvent, sender: str) -> None:
        self.task = None

    async def watch(
        self,
        end: datetime,
        recorder: EventRecorder,
        scheduler: str,
        progress: ProgressCallback | None,
        stop: asyncio.Event,
    ) -> bool:
        """Until ``end`` (True) or ``stop`` (False): progress and the plans of ``scheduler``."""
        start = self.clock.now()
        total = max(1.0, (end - start).total_seconds())
        # As every other client sees the plan: through the interface, not the module's attributes.
        planner = await self.proxy(scheduler, IRoboticScheduler)
        last_plan: Plan | None = None
        while self.clock.now() < end:
            plan = await planner.get_plan()
            if plan is not None and plan != last_plan:
                last_plan = plan
                recorder.record(SCHEDULE_RECORD, _plan_record(plan), sender=scheduler)
            if progress is not None:
                now = self.clock.now()
                sun = sun_altitude(self._where.latitude, self._where.longitude, now.timestamp())
                fraction = min(1.0, (now - start).total_seconds() / total)
                progress(NightProgress(now, sun, self.task, self.frames, fraction))
            try:
                # Clock seconds: on a virtual clock the night's record must not hang on wall time.
                async with self.clock.timeout(_WATCH_INTERVAL_S):
                    await stop.wait()
                return False
            except TimeoutError:
                pass
        return True


def _plan_record(plan: Plan) -> dict[str, Any]:
    return {
        "solver": plan.solver,
        "status": plan.status,
        "objective": plan.objective,
        "bound": plan.bound,
        "slots": [
            {"task": s.task_id, "start": s.start.isoformat(), "end": s.end.isoformat()} for s in plan.slots
        ],
    }
