"""A task archive read from a YAML file that people edit by hand, reloaded when it changes.

The file holds a list of request groups (or a mapping with the key ``request_groups``), each as in
a ``nightcrew tasks add`` file. Group names must be unique: task ids are ``<name>/<index>`` so they
stay the same across reloads. States and the schedule live in memory (the file is never written);
a task keeps its state over a reload unless its request changed. The file is polled on the clock
(modification time and size first, then a SHA-256 of the content); a file that became invalid is
reported and the last valid content stays in use, never half of the new one.
"""

from __future__ import annotations

import asyncio
import hashlib
import logging
import os
from collections.abc import Sequence
from datetime import datetime
from pathlib import Path

from nightcrew.clock import Clock
from nightcrew.config import InputPath, parse_yaml
from nightcrew.errors import ConfigError
from nightcrew.interfaces.quantities import PeriodOrOff
from nightcrew.robotic.archives._base import ScheduleStore
from nightcrew.robotic.archives._local import LocalTaskArchive, StatusChange, expired, schedule_changes
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import (
    SCHEDULABLE_STATES,
    InvalidTaskError,
    Task,
    TaskNotFoundError,
    TaskProblem,
    TaskState,
    parse_request_group,
    tasks_of_group,
)

__all__ = ["YamlTaskArchive"]

log = logging.getLogger(__name__)


class YamlTaskArchive(LocalTaskArchive, ScheduleStore):
    """Request groups from a YAML file.

    Args:
        path: The file.
        clock: Gives "now" and paces the polling.
        poll_interval: Clock seconds between checks of the file; 0: only :meth:`check_for_changes`.
    """

    def __init__(
        self,
        path: InputPath | os.PathLike[str],
        *,
        clock: Clock | None = None,
        poll_interval: PeriodOrOff = 10.0,
    ) -> None:
        super().__init__(clock=clock)
        self.path = Path(path)
        self.poll_interval = poll_interval
        #: The problem that kept the last change of the file from being used, if any.
        self.last_error: InvalidTaskError | None = None
        self._tasks: dict[str, Task] = {}
        self._schedule: list[PlannedSlot] = []
        self._stamp: tuple[int, int] | None = None
        self._digest = ""
        self._lock = asyncio.Lock()

    async def open(self) -> None:
        """Read the file (raises InvalidTaskError if it is invalid) and start polling."""
        await self.check_for_changes()
        if self.last_error is not None:
            raise self.last_error
        self._start_polling(str(self.path))

    async def close(self) -> None:
        await self._stop_polling()

    async def check_for_changes(self) -> bool:
        """Reload the file if it changed; whether the tasks changed (listeners hear which)."""
        stamp, text = await asyncio.to_thread(_blocking_read_if_changed, self.path, self._stamp)
        if text is None:
            return False
        self._stamp = stamp
        digest = hashlib.sha256(text.encode()).hexdigest()
        if digest == self._digest:
            return False  # touched, not changed
        try:
            fresh = _parse(text, str(self.path))
        except InvalidTaskError as exc:
            self.last_error = exc
            log.error("keeping the previous tasks: %s", exc)
            return False
        self._digest, self.last_error = digest, None
        async with self._lock:
            changed = self._merge(fresh)
        if changed:
            await self._notify(changed)
        return bool(changed)

    def _merge(self, fresh: dict[str, Task]) -> set[str]:
        changed = set(self._tasks) ^ set(fresh)
        merged: dict[str, Task] = {}
        for task_id, task in fresh.items():
            old = self._tasks.get(task_id)
            if old is not None and old.model_copy(update={"status": task.status}) == task:
                merged[task_id] = old  # same request: keep its state
            else:
                merged[task_id] = task
                changed.add(task_id)
        self._tasks = merged
        return changed

    async def get_task(self, task_id: str) -> Task:
        try:
            return self._tasks[task_id]
        except KeyError:
            raise TaskNotFoundError(f"no task {task_id!r} in {self.path}") from None

    async def list_tasks(self) -> list[Task]:
        """All tasks, in file order."""
        return list(self._tasks.values())

    async def get_schedulable_tasks(self) -> list[Task]:
        now = self.clock.now()
        async with self._lock:
            gone = [t for t in self._tasks.values() if expired(t, now)]
            for task in gone:
                self._tasks[task.id] = task.with_status(
                    task.status.transition(TaskState.WINDOW_EXPIRED, at=now)
                )
        if gone:
            await self._notify(task.id for task in gone)
        return [t for t in self._tasks.values() if t.status.state in SCHEDULABLE_STATES]

    async def _change_status(self, task_id: str, change: StatusChange) -> Task:
        async with self._lock:
            task = await self.get_task(task_id)
            updated = task.with_status(change(task))
            self._tasks[task_id] = updated
        return updated

    async def write_schedule(self, entries: Sequence[PlannedSlot], *, replace_from: datetime) -> None:
        async with self._lock:
            for entry in entries:
                await self.get_task(entry.task_id)  # an unknown task fails the whole schedule
            kept = [e for e in self._schedule if e.start < replace_from]
            self._schedule = sorted([*kept, *entries], key=lambda e: (e.start, e.task_id))
            planned = {e.task_id for e in self._schedule if e.end > replace_from}
            statuses = schedule_changes(self._tasks.values(), planned, self.clock.now())
            for task_id, status in statuses.items():
                self._tasks[task_id] = self._tasks[task_id].with_status(status)
        if statuses:
            await self._notify(statuses)

    async def read_schedule(
        self, *, start: datetime | None = None, end: datetime | None = None
    ) -> list[PlannedSlot]:
        return [
            e for e in self._schedule if (start is None or e.end > start) and (end is None or e.start < end)
        ]


def _blocking_read_if_changed(
    path: Path, stamp: tuple[int, int] | None
) -> tuple[tuple[int, int], str | None]:
    """The file's (mtime_ns, size) and its text, or None for the text if the stamp is unchanged."""
    info = path.stat()
    now = (info.st_mtime_ns, info.st_size)
    if now == stamp:
        return now, None
    return now, path.read_text(encoding="utf-8")


def _parse(text: str, source: str) -> dict[str, Task]:
    """All tasks of the file, or InvalidTaskError naming every problem."""
    try:
        data = parse_yaml(text, source)
    except ConfigError as exc:
        where = f"line {exc.line}: " if exc.line else ""
        raise InvalidTaskError([TaskProblem("", where + exc.message)], source=source) from None
    if isinstance(data, dict) and set(data) == {"request_groups"}:
        data = data["request_groups"]
    if data is None:
        data = []
    if not isinstance(data, list):
        problem = TaskProblem("", "expected a list of request groups (or a mapping with 'request_groups')")
        raise InvalidTaskError([problem], source=source)
    problems: list[TaskProblem] = []
    tasks: dict[str, Task] = {}
    names: set[str] = set()
    for index, entry in enumerate(data):
        try:
            group = parse_request_group(entry, prefix=f"[{index}]")
        except InvalidTaskError as exc:
            problems.extend(exc.problems)
            continue
        if group.name in names:
            problems.append(TaskProblem(f"[{index}].name", f"another group is called {group.name!r}"))
            continue
        names.add(group.name)
        ids = [f"{group.name}/{i}" for i in range(len(group.requests))]
        tasks.update((task.id, task) for task in tasks_of_group(group, group.name, ids))
    if problems:
        raise InvalidTaskError(problems, source=source)
    return tasks
