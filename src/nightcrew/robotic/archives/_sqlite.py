"""The SQLite task archive: the embedded default for robotic operation and ``nightcrew tasks``.

One worker thread owns the connection and runs every statement (functions named ``_blocking_*``),
so the event loop never waits on the disk and the connection is only ever used by one thread.
Every change is one transaction: a request group is stored with all its tasks or not at all.
Several processes may share the file (WAL journal, 5 s busy timeout); changes made by another
process (e.g. ``nightcrew tasks add`` while the robotic system runs) are noticed by polling
SQLite's ``data_version`` on the clock and reported to the listeners.
"""

from __future__ import annotations

import asyncio
import logging
import os
import sqlite3
from collections.abc import Callable, Collection, Sequence
from concurrent.futures import ThreadPoolExecutor
from datetime import datetime
from pathlib import Path
from typing import TypeVar

from nightcrew.clock import Clock
from nightcrew.config import DataPath
from nightcrew.errors import ModuleError
from nightcrew.interfaces.quantities import PeriodOrOff
from nightcrew.robotic.archives import _sqlite_schema as db
from nightcrew.robotic.archives._base import ScheduleStore
from nightcrew.robotic.archives._local import LocalTaskArchive, StatusChange, expired, schedule_changes
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import RequestGroup, Task, TaskError, TaskNotFoundError, TaskState, TaskStatus

__all__ = ["SqliteTaskArchive"]

log = logging.getLogger(__name__)
_T = TypeVar("_T")


class SqliteTaskArchive(LocalTaskArchive, ScheduleStore):
    """Tasks, their states and the schedule in one SQLite file.

    Args:
        path: The database file (created with its schema if missing).
        clock: Gives "now" and paces the polling.
        poll_interval: Clock seconds between checks for changes by other processes; 0: no polling.
    """

    def __init__(
        self,
        path: DataPath | os.PathLike[str],
        *,
        clock: Clock | None = None,
        poll_interval: PeriodOrOff = 10.0,
    ) -> None:
        super().__init__(clock=clock)
        self.path = Path(path)
        self.poll_interval = poll_interval
        self._executor: ThreadPoolExecutor | None = None
        self._conn: sqlite3.Connection | None = None
        self._data_version = 0

    async def open(self) -> None:
        if self._executor is not None:
            return
        self._executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="nightcrew-tasks-sqlite")
        try:
            await self._run(self._blocking_open)
        except BaseException:
            await self.close()
            raise
        self._start_polling(str(self.path))

    async def close(self) -> None:
        await self._stop_polling()
        executor, self._executor = self._executor, None
        if executor is None:
            return
        loop = asyncio.get_running_loop()
        await loop.run_in_executor(executor, self._blocking_close)
        executor.shutdown(wait=True)

    # --- adding, listing, reading --------------------------------------------------------------

    async def add_request_group(self, group: RequestGroup) -> list[Task]:
        """Store ``group`` with one PENDING task per request, all or nothing; return the tasks."""
        tasks = await self._run(self._blocking_add, group)
        await self._notify(task.id for task in tasks)
        return tasks

    async def list_tasks(self, *, states: Collection[TaskState] | None = None) -> list[Task]:
        """All tasks (or those in ``states``), by id."""
        return await self._run(self._blocking_list, tuple(states) if states is not None else None)

    async def list_unreadable(
        self, *, states: Collection[TaskState] | None = None
    ) -> list[db.UnreadableTask]:
        """The stored tasks (or those in ``states``) that the task model refuses, by id."""
        return await self._run(self._blocking_unreadable, tuple(states) if states is not None else None)

    async def get_task(self, task_id: str) -> Task:
        return await self._run(self._blocking_get, task_id)

    async def get_schedulable_tasks(self) -> list[Task]:
        now = self.clock.now()
        expired_ids = await self._run(self._blocking_expire, now)
        if expired_ids:
            await self._notify(expired_ids)
        return await self._run(
            self._blocking_list, (TaskState.PENDING, TaskState.SCHEDULED, TaskState.FAILED)
        )

    # --- the schedule ------------------------------------------------------------------------------

    async def write_schedule(self, entries: Sequence[PlannedSlot], *, replace_from: datetime) -> None:
        changed = await self._run(
            self._blocking_write_schedule, list(entries), replace_from, self.clock.now()
        )
        if changed:
            await self._notify(changed)

    async def read_schedule(
        self, *, start: datetime | None = None, end: datetime | None = None
    ) -> list[PlannedSlot]:
        return await self._run(self._blocking_read_schedule, start, end)

    async def _change_status(self, task_id: str, change: StatusChange) -> Task:
        return await self._run(self._blocking_change_status, task_id, change)

    # --- polling for other writers -------------------------------------------------------------

    async def check_for_changes(self) -> bool:
        """Whether another connection changed the database since the last check (listeners hear)."""
        version = await self._run(self._blocking_data_version)
        if version == self._data_version:
            return False
        self._data_version = version
        await self._notify()
        return True

    # --- blocking work, in the worker thread -------------------------------------------------------

    async def _run(self, function: Callable[..., _T], *args: object) -> _T:
        if self._executor is None:
            raise ModuleError(f"the task archive {self.path} is not open")
        return await asyncio.get_running_loop().run_in_executor(self._executor, function, *args)

    @property
    def _connection(self) -> sqlite3.Connection:
        assert self._conn is not None, "opened in _blocking_open"
        return self._conn

    def _blocking_open(self) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        # isolation_level=None: no implicit transactions; db.transaction() says where they are.
        conn = sqlite3.connect(self.path, isolation_level=None, timeout=5.0)
        try:
            conn.execute("PRAGMA foreign_keys = ON")
            conn.execute("PRAGMA journal_mode = WAL")
            db.migrate(conn)
        except BaseException:
            conn.close()
            raise
        self._conn = conn
        self._data_version = self._blocking_data_version()

    def _blocking_close(self) -> None:
        if self._conn is not None:
            self._conn.close()
            self._conn = None

    def _blocking_data_version(self) -> int:
        return int(self._connection.execute("PRAGMA data_version").fetchone()[0])

    def _blocking_add(self, group: RequestGroup) -> list[Task]:
        conn = self._connection
        with db.transaction(conn):
            group_id = db.insert_group(conn, group, self.clock.now())
            task_ids = [
                db.insert_task(conn, group_id, index, request) for index, request in enumerate(group.requests)
            ]
            tasks = db.select_tasks(conn, "t.group_id = ?", (group_id,))
        log.info("added request group %r (%d) with tasks %s", group.name, group_id, task_ids)
        return tasks

    def _blocking_list(self, states: tuple[TaskState, ...] | None) -> list[Task]:
        return db.select_tasks(self._connection, *_state_condition(states))

    def _blocking_unreadable(self, states: tuple[TaskState, ...] | None) -> list[db.UnreadableTask]:
        return db.select_rows(self._connection, *_state_condition(states))[1]

    def _blocking_get(self, task_id: str) -> Task:
        tasks, unreadable = db.select_rows(self._connection, "t.id = ?", (_row_id(task_id),))
        if unreadable:
            raise TaskError(f"task {task_id} in {self.path} cannot be read: {unreadable[0].problem}")
        if not tasks:
            raise TaskNotFoundError(f"no task {task_id!r} in {self.path}")
        return tasks[0]

    def _blocking_change_status(self, task_id: str, change: StatusChange) -> Task:
        conn = self._connection
        with db.transaction(conn):
            task = self._blocking_get(task_id)
            status = change(task)
            db.update_status(conn, task.id, status)
        return task.with_status(status)

    def _blocking_expire(self, now: datetime) -> list[str]:
        conn = self._connection
        with db.transaction(conn):
            due = db.select_tasks(conn, "t.last_window_end <= ?", (now.timestamp(),))
            changed: list[str] = []
            for task in due:
                if expired(task, now):
                    db.update_status(conn, task.id, task.status.transition(TaskState.WINDOW_EXPIRED, at=now))
                    changed.append(task.id)
        return changed

    def _blocking_write_schedule(
        self, entries: list[PlannedSlot], replace_from: datetime, now: datetime
    ) -> list[str]:
        conn = self._connection
        with db.transaction(conn):
            for entry in entries:
                self._blocking_get(entry.task_id)  # an unknown task fails the whole schedule
            db.replace_schedule(conn, entries, replace_from)
            planned = {e.task_id for e in db.select_schedule(conn, replace_from, None)}
            statuses: dict[str, TaskStatus] = schedule_changes(db.select_tasks(conn), planned, now)
            for task_id, status in statuses.items():
                db.update_status(conn, task_id, status)
        return list(statuses)

    def _blocking_read_schedule(self, start: datetime | None, end: datetime | None) -> list[PlannedSlot]:
        return db.select_schedule(self._connection, start, end)


def _state_condition(states: tuple[TaskState, ...] | None) -> tuple[str, list[object]]:
    """The SQL condition (and its parameters) for tasks in ``states``; none for all."""
    if states is None:
        return "", []
    return f"t.state IN ({', '.join('?' for _ in states)})", [s.value for s in states]


def _row_id(task_id: str) -> int:
    try:
        return int(task_id)
    except ValueError:
        raise TaskNotFoundError(f"no task {task_id!r}: task ids here are numbers") from None
