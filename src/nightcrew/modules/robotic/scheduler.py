"""The scheduler module: keeps a schedule of the night in a store, re-planning when things change.

It plans again when the archive's blocks change (polled), at once when tasks are added or withdrawn
(TasksChangedEvent, e.g. from ``nightcrew tasks add``), when a task fails (TaskFailedEvent: the
block is left out for the rest of the night, unless the event says it was interrupted from outside
and may run again, ``retryable``, or that a device failed under it, ``device_fault``: then it is
planned again no earlier than a back-off that doubles with each fault of that task, and left out
after ``max_device_faults``), when one starts or finishes (its slot is kept, done blocks leave; a
finished task re-plans at once), and when the weather turns good again (GoodWeatherEvent: from its
``eta`` on). Every plan names each task it leaves out with the reason (``Plan.unplanned``, logged
when it changes) and is announced by a ScheduleChangedEvent, on which the mastermind reads it at
once. The optimisation itself is :class:`nightcrew.robotic.scheduler.Scheduler`, run in a worker
thread.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import Callable, Sequence
from datetime import datetime, timedelta
from typing import Any, ClassVar, TypeVar

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.events import (
    GoodWeatherEvent,
    ScheduleChangedEvent,
    TaskFailedEvent,
    TaskFinishedEvent,
    TasksChangedEvent,
    TaskStartedEvent,
)
from nightcrew.interfaces import IRoboticScheduler, Plan, PlannedTask, UnplannedTask
from nightcrew.interfaces.quantities import Altitude, Period
from nightcrew.modules.module import Module
from nightcrew.modules.robotic._archive_option import built_option
from nightcrew.robotic.archive_ports import as_block_source, as_schedule_writer
from nightcrew.robotic.archives import ScheduleStore, TaskArchive
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.scheduler import Night, SchedulableBlock, Schedule, Scheduler
from nightcrew.robotic.scheduler.faults import DeviceFaults
from nightcrew.robotic.scheduler.ports import (
    BlockSource,
    MemoryScheduleStore,
    NamedBlockSource,
    ScheduleWriter,
    night_around,
)
from nightcrew.robotic.scheduler.scheduler import SolverName
from nightcrew.robotic.scheduler.sky import GridFit
from nightcrew.robotic.scheduler.slew import SlewModel

__all__ = ["SchedulerModule"]

log = logging.getLogger(__name__)

T = TypeVar("T")


class SchedulerModule(Module, IRoboticScheduler):
    """Plans the night from a task archive into a schedule store.

    Args:
        archive: Where the blocks come from: a block source or an archive of
            :mod:`nightcrew.robotic.archives` (an object or its description; one the module builds,
            also inside a block source, it opens and closes, see :mod:`._archive_option`).
        store: Where the schedule goes: a schedule writer or an archive's schedule store. By
            default the archive's own schedule store when it keeps one (so a mastermind in another
            process reads the plan), else in memory
            (:class:`~nightcrew.robotic.scheduler.ports.MemoryScheduleStore`).
        solver: ``mip`` (optimal) or ``priority`` (astroplan's greedy).
        step_s: Time slice of the scheduler, seconds.
        slew_overhead_s: Worst-case slew and settling added to every block, seconds.
        meridian_flip_s: Time a meridian flip takes on a German-equatorial mount, seconds, added to
            every block whose target may cross the meridian in it (docs/mounts.md); 0: no flips.
        time_limit_s: Kept for older configuration files; decides nothing (the MIP stops at a
            node limit, so the plan does not depend on the machine's load).
        slew: The mount's slew model (``slew_rate`` or ``axis_rates``, ``acceleration``,
            ``settle_time``, ``mount``, ``dome_rate``, ``filter_change_s``,
            ``instrument_setup_s``; :class:`~nightcrew.robotic.scheduler.slew.SlewModel`): every
            transition is then priced exactly and ``slew_overhead_s`` is not used. Give the
            mastermind the same, so it judges fits with the same slews.
        poll_interval_s: How often to look for changed blocks, clock seconds.
        max_sun_altitude: The night is while the Sun is below this altitude (degrees).
        device_fault_backoff_s: After a device failed under a task, it is planned again no earlier
            than this many clock seconds later, doubled for each further fault of that task.
        max_device_faults: After this many device faults a task is left out for the night.
    """

    #: Built here (a relative path read against the file's folder), opened and closed with the module.
    config_builds_itself: ClassVar[frozenset[str]] = Module.config_builds_itself | {"archive", "store"}

    def __init__(
        self,
        *,
        archive: BlockSource | TaskArchive | dict[str, Any],
        store: ScheduleWriter | ScheduleStore | dict[str, Any] | None = None,
        solver: SolverName = "mip",
        step_s: float = 300.0,
        slew_overhead_s: float = 100.0,
        meridian_flip_s: float = 0.0,
        time_limit_s: float = 10.0,
        poll_interval_s: Period = 60.0,
        max_sun_altitude: Altitude = -12.0,
        device_fault_backoff_s: float = 300.0,
        max_device_faults: int = 3,
        slew: dict[str, Any] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        try:
            slew_model = None if slew is None else SlewModel.from_config(slew)
        except InvalidArgumentError as exc:
            raise ConfigError(str(exc), key="slew") from None
        # Archives of nightcrew.robotic.archives are wrapped by the adapters; opened with us.
        self._archive_option = built_option(archive, object, "archive", self)
        default_store = self._archive_option.archive
        if not isinstance(default_store, ScheduleStore):
            default_store = None
        self._store_option = built_option(
            store or default_store or MemoryScheduleStore(), object, "store", self
        )
        self._archive: BlockSource = _adapted(as_block_source, self._archive_option.value, "archive")
        self._store: ScheduleWriter = _adapted(as_schedule_writer, self._store_option.value, "store")
        try:
            self._scheduler = Scheduler(
                solver=solver,
                step_s=step_s,
                slew_overhead_s=slew_overhead_s,
                meridian_flip_s=meridian_flip_s,
                time_limit_s=time_limit_s,
                slew=slew_model,
            )
        except InvalidArgumentError as exc:
            raise ConfigError(str(exc), key=str(exc).split()[0]) from exc
        # Calibration tasks (no target) are placed at our site, sky flats fitted to our grid.
        fit = GridFit(step_s=step_s, slew_overhead_s=slew_overhead_s)
        self._archive = as_block_source(self._archive, site=self.site, fit=fit)
        self._poll_interval = poll_interval_s
        self._max_sun_altitude = max_sun_altitude
        self._replan_wanted = asyncio.Event()
        self._not_before: datetime | None = None  # after bad weather: plan from the eta on
        self._failed: dict[str, str] = {}  # task id → why it is left out for the night
        self._faults = DeviceFaults(backoff_s=device_fault_backoff_s, limit=max_device_faults)
        self._logged_reasons: dict[str, str] = {}
        self._done: set[str] = set()
        self._in_progress: PlannedSlot | None = None
        self._last_blocks: tuple[SchedulableBlock, ...] | None = None
        #: The last schedule made (for status displays and tests).
        self.schedule: Schedule | None = None
        self._plan: Plan | None = None
        self.add_background_task(self._replan_loop, name="replan loop")

    async def open(self) -> None:
        # Before the replan loop starts (super().open()): it reads the archive at once.
        await self._archive_option.open()
        await self._store_option.open()
        await super().open()
        await self.comm.register_event(TaskFailedEvent, self.on_task_failed)
        await self.comm.register_event(TaskStartedEvent, self.on_task_started)
        await self.comm.register_event(TaskFinishedEvent, self.on_task_finished)
        await self.comm.register_event(GoodWeatherEvent, self.on_good_weather)
        await self.comm.register_event(TasksChangedEvent, self.on_tasks_changed)

    async def close(self) -> None:
        await super().close()
        await self._store_option.close()
        await self._archive_option.close()

    # --- events ---------------------------------------------------------------------------------

    async def on_task_failed(self, event: TaskFailedEvent, sender: str) -> None:
        if event.device_fault:  # the device failed, not the task: again later, within a limit
            retry_at = self._faults.record(event.id, self.clock.now())
            if retry_at is None:
                log.info("task %s: device fault (%s), the last allowed: left out", event.id, event.reason)
                self._failed[event.id] = f"left out after {self._faults.limit} device faults ({event.reason})"
            else:
                log.info(
                    "task %s: device fault (%s): planned again from %s",
                    event.id,
                    event.reason,
                    f"{retry_at:%H:%M:%S}",
                )
        elif event.retryable:  # interrupted (weather, dawn ...): plan it again with what is left
            log.info("task %s was interrupted (%s): re-planning with it", event.id, event.reason)
        else:
            log.info("task %s failed (%s): re-planning without it", event.id, event.reason)
            self._failed[event.id] = f"failed tonight ({event.reason})"
        if self._in_progress is not None and self._in_progress.task_id == event.id:
            self._in_progress = None
        self._replan_wanted.set()

    async def on_task_started(self, event: TaskStartedEvent, sender: str) -> None:
        now = self.clock.now()
        # Without an end still ahead (a planned slot ends after it starts): one time slice.
        end = (
            event.eta
            if event.eta is not None and event.eta > now
            else now + timedelta(seconds=self._scheduler.step_s)
        )
        self._in_progress = PlannedSlot(event.id, now, end)

    async def on_task_finished(self, event: TaskFinishedEvent, sender: str) -> None:
        self._done.add(event.id)
        if self._in_progress is not None and self._in_progress.task_id == event.id:
            self._in_progress = None
        # At once, not at the next poll: a task that ended before its slot leaves a gap that only
        # a new plan fills (the next slot may be too far ahead to start early).
        self._replan_wanted.set()

    async def on_tasks_changed(self, event: TasksChangedEvent, sender: str) -> None:
        log.info("tasks %s (%s by %s): re-planning", event.change, ", ".join(event.ids), sender)
        self._replan_wanted.set()

    async def on_good_weather(self, event: GoodWeatherEvent, sender: str) -> None:
        log.info("weather is good again: re-planning")
        self._not_before = event.eta
        self._replan_wanted.set()

    # --- planning -------------------------------------------------------------------------------

    async def _replan_loop(self) -> None:
        while True:
            blocks = tuple(await self._archive.get_schedulable_blocks())
            lapse = self._next_lapse()
            lapsed = lapse is not None and lapse <= self.clock.now()
            if self._replan_wanted.is_set() or blocks != self._last_blocks or lapsed:
                self._replan_wanted.clear()
                self._last_blocks = blocks
                await self.replan(blocks)
            wait = self._poll_interval
            lapse = self._next_lapse()
            if lapse is not None:
                wait = min(wait, max(1.0, (lapse - self.clock.now()).total_seconds()))
            with contextlib.suppress(TimeoutError):
                async with self.clock.timeout(wait):
                    await self._replan_wanted.wait()

    def _next_lapse(self) -> datetime | None:
        """When the first slot of the plan ends unstarted, if no task runs: the plan is stale then.

        A slot lapses when the mastermind could not start it in time (e.g. it first opened the
        roof and focused); without a new plan the task would wait for the next poll.
        """
        if self.schedule is None or self._in_progress is not None:
            return None
        settled = self._done | self._failed.keys()
        ends = [slot.end for slot in self.schedule.slots if slot.task_id not in settled]
        return min(ends, default=None)

    async def replan(self, blocks: Sequence[SchedulableBlock]) -> Schedule:
        """Plan the rest of the night now and write it to the store."""
        now = self.clock.now()
        start = max(now, self._not_before) if self._not_before is not None else now
        if self.site is None:
            raise ConfigError("the scheduler needs the observatory's site", key="site")
        night = night_around(self.site, start, max_sun_altitude=self._max_sun_altitude)
        self._faults.start_night(night.end)
        exclude = frozenset(self._failed.keys() | self._done)
        held_back = self._faults.hold_back(blocks, night)
        names = await self._archive.block_names() if isinstance(self._archive, NamedBlockSource) else {}
        async with self.clock.work("schedule"):
            schedule, reasons = await asyncio.to_thread(
                self._blocking_solve, held_back, night, start, exclude, self._in_progress, names
            )
        known = {block.id for block in blocks}
        reasons.update({task_id: why for task_id, why in self._failed.items() if task_id in known})
        for task_id in reasons.keys() & self._faults.retry_at.keys():
            retry_at = self._faults.retry_at[task_id]
            if retry_at > start:  # the back-off is what keeps it out
                reasons[task_id] = f"device fault: not before {retry_at:%H:%M:%S} UTC; " + reasons[task_id]
        self.schedule = schedule
        self._plan = plan_of(schedule, blocks, night, now, names, reasons)
        self._log_reasons(reasons, names)
        await self._store.set_schedule(schedule.slots, now)
        # The mastermind reads the new plan at once: a task that ended early leaves no idle poll.
        await self.comm.send_event(ScheduleChangedEvent(ids=tuple(slot.task_id for slot in schedule.slots)))
        log.info(
            "planned %d blocks from %s (%s, objective %.2f, %.1f s)",
            len(schedule.slots),
            f"{start:%H:%M}",
            schedule.status,
            schedule.objective,
            schedule.wall_time_s,
        )
        return schedule

    @property
    def task_archive(self) -> TaskArchive | None:
        """The task archive the blocks come from, where it is one (or a block source wraps one)."""
        return self._archive_option.archive

    async def get_plan(self) -> Plan | None:
        return self._plan

    def _log_reasons(self, reasons: dict[str, str], names: dict[str, str]) -> None:
        """Log why each task is left out, once per change of its reason."""
        for task_id, reason in sorted(reasons.items()):
            if self._logged_reasons.get(task_id) != reason:
                log.info("task %s (%s) not planned: %s", task_id, names.get(task_id, "?"), reason)
        self._logged_reasons = dict(reasons)

    def _blocking_solve(
        self,
        blocks: list[SchedulableBlock],
        night: Night,
        start: datetime,
        exclude: frozenset[str],
        in_progress: PlannedSlot | None,
        names: dict[str, str],
    ) -> tuple[Schedule, dict[str, str]]:
        scheduler = self._scheduler
        schedule = scheduler.schedule(blocks, night, now=start, exclude=exclude, in_progress=in_progress)
        reasons = scheduler.explain(
            blocks, night, schedule, now=start, exclude=exclude, in_progress=in_progress, names=names
        )
        return schedule, reasons


def plan_of(
    schedule: Schedule,
    blocks: Sequence[SchedulableBlock],
    night: Night,
    planned_at: datetime,
    names: dict[str, str] | None = None,
    reasons: dict[str, str] | None = None,
) -> Plan:
    """The plan as IRoboticScheduler shows it (``names``: block id → task name, where known;
    ``reasons``: task id → why it is left out)."""
    names = names or {}
    priorities = {block.id: block.priority for block in blocks}
    return Plan(
        planned_at=planned_at,
        night_start=night.start,
        night_end=night.end,
        solver=schedule.solver,
        status=schedule.status,
        objective=schedule.objective,
        bound=schedule.bound,
        gap=schedule.gap,
        wall_time_s=schedule.wall_time_s,
        slots=tuple(
            PlannedTask(
                task_id=s.task_id,
                start=s.start,
                end=s.end,
                priority=priorities.get(s.task_id),
                name=names.get(s.task_id),
            )
            for s in schedule.slots
        ),
        unplanned=tuple(
            UnplannedTask(task_id=task_id, reason=reason, name=names.get(task_id))
            for task_id, reason in sorted((reasons or {}).items())
        ),
    )


def _adapted(adapt: Callable[[object], T], value: object, key: str) -> T:
    try:
        return adapt(value)
    except TypeError as exc:
        raise ConfigError(str(exc), key=key) from exc
