"""The schedule around now as the mastermind reads it: slots with what deciding needs from their tasks."""

from __future__ import annotations

import logging
from datetime import datetime, timedelta

from nightcrew.object import Object
from nightcrew.robotic.archives import ScheduleStore, TaskArchive
from nightcrew.robotic.mastermind._decide import Slot
from nightcrew.robotic.mastermind._tasks import interruption_reason, slot_for
from nightcrew.robotic.tasks import Task, TaskNotFoundError, TaskState

__all__ = ["ScheduleReader"]

log = logging.getLogger(__name__)


class ScheduleReader:
    """Reads the schedule from now to ``horizon`` ahead as :class:`Slot` values.

    It remembers the slots in which a task failed by its own fault, so such a slot is not
    runnable again (a broken task is not retried in a loop).

    Args:
        host: The module whose name prefixes log lines.
        store: Where the schedule is read.
        archive: Where the scheduled tasks are.
        horizon: How far ahead of now the schedule is read.
        max_sun_altitude, twilight_max_sun_altitude: The observatory's caps (see ``sun_limits``).
    """

    def __init__(
        self,
        host: Object,
        store: ScheduleStore,
        archive: TaskArchive,
        *,
        horizon: timedelta,
        max_sun_altitude: float,
        twilight_max_sun_altitude: float,
    ) -> None:
        self._host, self._store, self._archive, self._horizon = host, store, archive, horizon
        self._sun_caps = {
            "max_sun_altitude": max_sun_altitude,
            "twilight_max_sun_altitude": twilight_max_sun_altitude,
        }
        self._failed_slots: set[tuple[str, datetime]] = set()  # (task, slot start)

    def failed_in(self, task_id: str, start: datetime) -> None:
        """The task failed by its own fault in its slot that starts at ``start``: not again there."""
        self._failed_slots.add((task_id, start))

    async def read(self, now: datetime) -> tuple[list[Slot], dict[str, Task]]:
        """The slots from ``now`` to the horizon, and their tasks by id."""
        planned_slots = await self._store.read_schedule(start=now, end=now + self._horizon)
        slots: list[Slot] = []
        tasks: dict[str, Task] = {}
        for planned in planned_slots:
            try:
                task = tasks.get(planned.task_id) or await self._archive.get_task(planned.task_id)
            except TaskNotFoundError:
                name = self._host.context_name
                log.warning("%s: scheduled task %s is not in the archive", name, planned.task_id)
                continue
            tasks[task.id] = task
            failed_here = (task.id, planned.start) in self._failed_slots
            slots.append(slot_for(planned, task, failed_here=failed_here, **self._sun_caps))
        return slots, tasks

    async def recover_orphans(self, now: datetime) -> None:
        """Tasks left RUNNING in the schedule of the last day (we were killed mid-task) become FAILED.

        Assumes one mastermind per archive; the progress recorded so far is kept.
        """
        for planned in await self._store.read_schedule(start=now - timedelta(days=1), end=now):
            task = await self._archive.get_task(planned.task_id)
            if task.state is TaskState.RUNNING:
                reason = interruption_reason("a restart of the mastermind", task, task.status.progress)
                log.warning("%s: task %s was left running: %s", self._host.context_name, task.id, reason)
                await self._archive.mark_failed(task.id, reason, task.status.progress)
