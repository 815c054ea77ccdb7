"""The part shared by archives that keep task states themselves (SQLite, YAML file).

Every state change is a function ``TaskStatus -> TaskStatus`` (built from
:meth:`TaskStatus.transition`), applied by the archive's one :meth:`_change_status` method, so the
state table is enforced in one place and listeners hear of every change.
"""

from __future__ import annotations

from abc import abstractmethod
from collections.abc import Callable, Iterable
from datetime import datetime

from nightcrew.robotic.archives._base import TaskArchive
from nightcrew.robotic.tasks import SCHEDULABLE_STATES, Task, TaskProgress, TaskState, TaskStatus

__all__ = ["LocalTaskArchive", "StatusChange", "expired", "schedulable_at", "schedule_changes"]

#: How a task's status changes (given the task, for shape checks).
StatusChange = Callable[[Task], TaskStatus]


def schedulable_at(task: Task, now: datetime) -> bool:
    """Whether the scheduler may place ``task`` at ``now``: schedulable state, a window left."""
    return task.status.state in SCHEDULABLE_STATES and task.request.last_end > now


def expired(task: Task, now: datetime) -> bool:
    """Whether ``task`` should become WINDOW_EXPIRED: still to do, but its last window is over."""
    return task.status.state in SCHEDULABLE_STATES and task.request.last_end <= now


def schedule_changes(tasks: Iterable[Task], scheduled_ids: set[str], now: datetime) -> dict[str, TaskStatus]:
    """New statuses after a schedule is written: planned tasks SCHEDULED, dropped ones PENDING."""
    changes: dict[str, TaskStatus] = {}
    for task in tasks:
        state = task.status.state
        if task.id in scheduled_ids and state in (TaskState.PENDING, TaskState.FAILED):
            changes[task.id] = task.status.transition(TaskState.SCHEDULED, at=now)
        elif task.id not in scheduled_ids and state is TaskState.SCHEDULED:
            changes[task.id] = task.status.transition(TaskState.PENDING, at=now)
    return changes


class LocalTaskArchive(TaskArchive):
    """An archive that stores statuses itself; subclasses provide :meth:`_change_status`."""

    @abstractmethod
    async def _change_status(self, task_id: str, change: StatusChange) -> Task:
        """Apply ``change`` to the task's current status atomically, store it, return the task."""

    async def mark_started(self, task_id: str) -> Task:
        return await self._changed(
            task_id, lambda task: task.status.transition(TaskState.RUNNING, at=self._now())
        )

    async def record_progress(self, task_id: str, progress: TaskProgress) -> Task:
        def change(task: Task) -> TaskStatus:
            progress.check_fits(task.request)
            return task.status.with_progress(progress, at=self._now())

        return await self._changed(task_id, change)

    async def mark_finished(self, task_id: str, progress: TaskProgress) -> Task:
        def change(task: Task) -> TaskStatus:
            progress.check_fits(task.request)
            return task.status.transition(TaskState.COMPLETED, at=self._now(), progress=progress)

        return await self._changed(task_id, change)

    async def mark_failed(self, task_id: str, reason: str, progress: TaskProgress) -> Task:
        def change(task: Task) -> TaskStatus:
            progress.check_fits(task.request)
            return task.status.transition(TaskState.FAILED, at=self._now(), reason=reason, progress=progress)

        return await self._changed(task_id, change)

    async def cancel(self, task_id: str, reason: str) -> Task:
        """Withdraw a task that has not ended (CANCELED, with ``reason``)."""
        return await self._changed(
            task_id, lambda task: task.status.transition(TaskState.CANCELED, at=self._now(), reason=reason)
        )

    async def _changed(self, task_id: str, change: StatusChange) -> Task:
        task = await self._change_status(task_id, change)
        await self._notify([task_id])
        return task

    def _now(self) -> datetime:
        return self.clock.now()
