"""Recording what happens to a task: its start, its progress in the background, its end, the events."""

from __future__ import annotations

import asyncio
import logging
from datetime import datetime

from nightcrew.errors import NightcrewError
from nightcrew.events import TaskFailedEvent, TaskFinishedEvent, TaskStartedEvent
from nightcrew.object import Object
from nightcrew.robotic.archives import TaskArchive
from nightcrew.robotic.mastermind._tasks import kept_progress
from nightcrew.robotic.tasks import InvalidTransitionError, Task, TaskProgress

__all__ = ["TaskRecorder"]

log = logging.getLogger(__name__)


class TaskRecorder:
    """Keeps the running task and its progress and records them in the archive and on the bus.

    Progress is written by one background writer, so the exposure loop never waits for the
    database; the end of a task is recorded after its last progress.

    Args:
        host: The module whose comm is used (and whose name prefixes log lines).
        archive: Where the task's fate goes.
    """

    def __init__(self, host: Object, archive: TaskArchive) -> None:
        self._host, self._archive = host, archive
        self.current: Task | None = None  # the running task
        self.progress = TaskProgress()  # of the running (or last) task, never shrinking
        self._writer: asyncio.Task[None] | None = None

    async def started(self, task: Task, *, eta: datetime) -> Task:
        """Mark ``task`` RUNNING and announce it; returns it as the archive has it now."""
        task = await self._archive.mark_started(task.id)
        self.current, self.progress = task, task.status.progress
        log.info("%s: task %s (%s) started", self._host.context_name, task.id, task.name)
        await self._host.comm.send_event(TaskStartedEvent(name=task.name, id=task.id, eta=eta))
        return task

    async def on_progress(self, progress: TaskProgress) -> None:
        """A run's progress report (the runner's callback)."""
        task = self.current
        if task is None:
            return
        self.progress = kept_progress(self.progress, progress)
        # A database transaction must not hold up the next exposure: one writer records the latest.
        if self._writer is None or self._writer.done():
            self._writer = asyncio.create_task(self._write_progress(task))

    async def ended(
        self, task: Task, reason: str | None, *, retryable: bool = False, device_fault: bool = False
    ) -> None:
        """Mark the task finished (``reason`` None) or failed in the archive, and tell everybody.

        ``retryable``: it was interrupted from outside and may be planned again; ``device_fault``:
        a device failed under it (see TaskFailedEvent).
        """
        self.current = None
        writer, self._writer = self._writer, None
        if writer is not None:
            await asyncio.wait({writer})  # the end is recorded after the last progress
        name, progress = self._host.context_name, self.progress
        try:
            if reason is None:
                await self._archive.mark_finished(task.id, progress)
            else:
                await self._archive.mark_failed(task.id, reason, progress)
        except InvalidTransitionError as exc:  # cancelled while it ran: the cancellation stands
            log.info("%s: task %s (%s) was cancelled while it ran: %s", name, task.id, task.name, exc)
            retryable = False
        except Exception:
            log.exception("%s: could not record the end of task %s in the archive", name, task.id)
        if reason is None:
            log.info("%s: task %s (%s) finished", name, task.id, task.name)
            event: TaskFinishedEvent | TaskFailedEvent = TaskFinishedEvent(name=task.name, id=task.id)
        else:
            log.warning("%s: task %s (%s) failed: %s", name, task.id, task.name, reason)
            event = TaskFailedEvent(
                name=task.name, id=task.id, reason=reason, retryable=retryable, device_fault=device_fault
            )
        try:
            await self._host.comm.send_event(event)
        except NightcrewError as exc:
            log.error("%s: could not announce the end of task %s: %s", name, task.id, exc)

    async def _write_progress(self, task: Task) -> None:
        written: TaskProgress | None = None
        while written != self.progress:
            written = self.progress
            try:
                await self._archive.record_progress(task.id, written)
            except Exception as exc:  # kept in memory and recorded at the end
                log.warning(
                    "%s: could not record the progress of task %s: %s", self._host.context_name, task.id, exc
                )
                return
