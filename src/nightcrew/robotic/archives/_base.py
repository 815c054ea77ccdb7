"""What every task archive and schedule store offers.

A :class:`TaskArchive` hands out tasks and records what happens to them; a :class:`ScheduleStore`
keeps the schedule (which task runs when). An archive that owns its tasks (SQLite, a YAML file)
implements both, the LCO portal client too. Listeners hear of every change as a
:class:`TaskChange`, so a scheduler can plan again when tasks come, go or change.
"""

from __future__ import annotations

import asyncio
import contextlib
import inspect
import logging
from abc import ABC, abstractmethod
from collections.abc import Awaitable, Callable, Iterable, Sequence
from dataclasses import dataclass
from datetime import datetime
from types import TracebackType
from typing import Self

from nightcrew.clock import Clock, RealClock
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import Task, TaskProgress

__all__ = ["ScheduleStore", "TaskArchive", "TaskChange", "TaskListener"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class TaskChange:
    """Tasks were added, changed or removed; an empty ``task_ids`` means "any of them"."""

    task_ids: frozenset[str] = frozenset()


#: Called with every change; may be a coroutine function.
TaskListener = Callable[[TaskChange], Awaitable[None] | None]


class TaskArchive(ABC):
    """Where the tasks come from and where their fate goes.

    Use as ``async with archive:`` (or ``open()``/``close()``); constructors do no I/O.

    Args:
        clock: Gives "now" (window expiry, timestamps) and paces polling.
    """

    #: Clock seconds between checks for changes made elsewhere (0: none); set by subclasses.
    poll_interval: float = 0.0

    def __init__(self, *, clock: Clock | None = None) -> None:
        self.clock: Clock = clock or RealClock()
        self._listeners: list[TaskListener] = []
        self._poll_task: asyncio.Task[None] | None = None

    async def open(self) -> None:  # noqa: B027 - optional hook, empty by default
        """Acquire resources (connections, polling tasks)."""

    async def close(self) -> None:  # noqa: B027 - optional hook, empty by default
        """Release them; safe to call twice."""

    async def check_for_changes(self) -> bool:
        """Whether tasks changed elsewhere since the last check (listeners hear); none by default."""
        return False

    def _start_polling(self, source: str) -> None:
        """Call :meth:`check_for_changes` every ``poll_interval`` clock seconds until closed."""
        if self.poll_interval > 0 and self._poll_task is None:
            self._poll_task = asyncio.create_task(self._poll_loop(source), name=f"poll {source}")

    async def _stop_polling(self) -> None:
        task, self._poll_task = self._poll_task, None
        if task is not None:
            task.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await task

    async def _poll_loop(self, source: str) -> None:
        while True:
            await self.clock.sleep(self.poll_interval)
            try:
                await self.check_for_changes()
            except Exception as exc:  # a failed look (file, database, portal) is retried next time
                log.warning("cannot check %s for changes: %s", source, exc)

    async def __aenter__(self) -> Self:
        await self.open()
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        await self.close()

    def add_listener(self, listener: TaskListener) -> None:
        """Call ``listener`` on every change of tasks."""
        self._listeners.append(listener)

    def remove_listener(self, listener: TaskListener) -> None:
        """Stop calling ``listener``."""
        self._listeners.remove(listener)

    async def _notify(self, task_ids: Iterable[str] = ()) -> None:
        change = TaskChange(frozenset(task_ids))
        for listener in list(self._listeners):
            try:
                result = listener(change)
                if inspect.isawaitable(result):
                    await result
            except Exception:  # a broken listener must not break the archive or the other listeners
                log.exception("task listener %r failed", listener)

    @abstractmethod
    async def get_schedulable_tasks(self) -> list[Task]:
        """Tasks the scheduler may place now: schedulable state and a window not yet over."""

    @abstractmethod
    async def get_task(self, task_id: str) -> Task:
        """The task ``task_id``; raises TaskNotFoundError if there is none."""

    @abstractmethod
    async def mark_started(self, task_id: str) -> Task:
        """The task is being observed (RUNNING)."""

    @abstractmethod
    async def record_progress(self, task_id: str, progress: TaskProgress) -> Task:
        """What a RUNNING task has done so far, so an interruption loses nothing."""

    @abstractmethod
    async def mark_finished(self, task_id: str, progress: TaskProgress) -> Task:
        """The task ended as planned (COMPLETED) having done ``progress``."""

    @abstractmethod
    async def mark_failed(self, task_id: str, reason: str, progress: TaskProgress) -> Task:
        """The task ended early (FAILED) for ``reason`` having done ``progress``."""


class ScheduleStore(ABC):
    """Keeps the schedule: planned slots (task id, start, end), as the scheduler made them."""

    @abstractmethod
    async def write_schedule(self, entries: Sequence[PlannedSlot], *, replace_from: datetime) -> None:
        """Replace the slots starting at or after ``replace_from`` by ``entries``.

        Earlier slots (the past, the task running now) stay as they are.
        """

    @abstractmethod
    async def read_schedule(
        self, *, start: datetime | None = None, end: datetime | None = None
    ) -> list[PlannedSlot]:
        """Slots overlapping ``[start, end)`` (all if not given), by start time."""
