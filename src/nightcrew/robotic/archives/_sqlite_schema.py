"""The SQLite task database: schema migrations and the blocking statements the archive runs.

Everything here is synchronous and runs in the archive's worker thread. The schema version lives
in the table ``schema_version``; :data:`MIGRATIONS` ``[n]`` takes a database from version ``n`` to
``n + 1``, each in its own transaction, so a new release upgrades old files on open.
"""

from __future__ import annotations

import logging
import sqlite3
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from datetime import UTC, datetime

from pydantic import ValidationError

from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import Request, RequestGroup, Task, TaskStatus
from nightcrew.robotic.tasks._errors import TaskError
from nightcrew.robotic.tasks._validation import problems_of

__all__ = ["MIGRATIONS", "SCHEMA_VERSION", "UnreadableTask", "migrate", "transaction"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class UnreadableTask:
    """A stored task the task model refuses (e.g. stored before a bound it breaks existed)."""

    id: str
    name: str
    problem: str


MIGRATIONS: tuple[str, ...] = (
    # 0 -> 1: request groups, one task per request, the schedule.
    """
    CREATE TABLE request_groups (
        id INTEGER PRIMARY KEY AUTOINCREMENT,
        name TEXT NOT NULL,
        proposal TEXT NOT NULL,
        observation_type TEXT NOT NULL,
        priority REAL NOT NULL,
        ipp REAL NOT NULL,
        created_at TEXT NOT NULL
    );
    CREATE TABLE tasks (
        id INTEGER PRIMARY KEY AUTOINCREMENT,
        group_id INTEGER NOT NULL REFERENCES request_groups (id) ON DELETE CASCADE,
        request_index INTEGER NOT NULL,
        request TEXT NOT NULL,          -- the Request as JSON
        state TEXT NOT NULL,            -- copy of status.state, for queries
        status TEXT NOT NULL,           -- the TaskStatus as JSON
        last_window_end REAL NOT NULL,  -- Unix seconds: after it the task expires
        UNIQUE (group_id, request_index)
    );
    CREATE INDEX tasks_by_state ON tasks (state);
    CREATE TABLE schedule (
        task_id INTEGER NOT NULL REFERENCES tasks (id) ON DELETE CASCADE,
        start REAL NOT NULL,
        end REAL NOT NULL
    );
    CREATE INDEX schedule_by_start ON schedule (start);
    """,
)
#: The version this code writes.
SCHEMA_VERSION = len(MIGRATIONS)


@contextmanager
def transaction(conn: sqlite3.Connection) -> Iterator[sqlite3.Connection]:
    """``BEGIN IMMEDIATE`` ... ``COMMIT``, or ``ROLLBACK`` on any error: all or nothing.

    IMMEDIATE takes the write lock at the start, so two writers wait (busy timeout) instead of
    failing half-way when both try to upgrade a read lock.
    """
    conn.execute("BEGIN IMMEDIATE")
    try:
        yield conn
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")


def migrate(conn: sqlite3.Connection) -> int:
    """Bring the database to :data:`SCHEMA_VERSION`; return the version found."""
    with transaction(conn):
        conn.execute("CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL)")
        row = conn.execute("SELECT version FROM schema_version").fetchone()
        if row is None:
            conn.execute("INSERT INTO schema_version (version) VALUES (0)")
        found = int(row[0]) if row else 0
    if found > SCHEMA_VERSION:
        raise TaskError(
            f"the task database has schema version {found}; this nightcrew knows {SCHEMA_VERSION}"
        )
    for version in range(found, SCHEMA_VERSION):
        with transaction(conn):
            for statement in _statements(MIGRATIONS[version]):
                conn.execute(statement)
            conn.execute("UPDATE schema_version SET version = ?", (version + 1,))
    return found


def _statements(script: str) -> Iterator[str]:
    # executescript() would COMMIT on its own; single statements keep the migration in our transaction.
    for statement in script.split(";"):
        lines = [line.split("--", 1)[0] for line in statement.splitlines()]
        text = "\n".join(lines).strip()
        if text:
            yield text


def insert_group(conn: sqlite3.Connection, group: RequestGroup, now: datetime) -> int:
    """Insert the group row; return its id."""
    cursor = conn.execute(
        "INSERT INTO request_groups (name, proposal, observation_type, priority, ipp, created_at)"
        " VALUES (?, ?, ?, ?, ?, ?)",
        (
            group.name,
            group.proposal,
            group.observation_type.value,
            group.priority,
            group.ipp,
            now.isoformat(),
        ),
    )
    return int(cursor.lastrowid or 0)


def insert_task(conn: sqlite3.Connection, group_id: int, index: int, request: Request) -> int:
    """Insert one PENDING task for ``request``; return its id."""
    status = TaskStatus()
    cursor = conn.execute(
        "INSERT INTO tasks (group_id, request_index, request, state, status, last_window_end)"
        " VALUES (?, ?, ?, ?, ?, ?)",
        (
            group_id,
            index,
            request.model_dump_json(),
            status.state.value,
            status.model_dump_json(),
            request.last_end.timestamp(),
        ),
    )
    return int(cursor.lastrowid or 0)


_TASK_COLUMNS = (
    "SELECT t.id, t.group_id, g.name, g.proposal, g.observation_type, g.priority, g.ipp, t.request_index,"
    " t.request, t.status FROM tasks t JOIN request_groups g ON g.id = t.group_id"
)


def select_tasks(conn: sqlite3.Connection, where: str = "", parameters: Sequence[object] = ()) -> list[Task]:
    """Tasks matching the SQL condition ``where`` (on ``t`` = tasks, ``g`` = groups), by id.

    A row that cannot be read is left out with a warning naming it (one bad row must not stop
    the scheduler or ``tasks list``); :func:`select_rows` says which.
    """
    tasks, unreadable = select_rows(conn, where, parameters)
    for row in unreadable:
        log.warning("task %s (%s) cannot be read and is left out: %s", row.id, row.name, row.problem)
    return tasks


def select_rows(
    conn: sqlite3.Connection, where: str = "", parameters: Sequence[object] = ()
) -> tuple[list[Task], list[UnreadableTask]]:
    """The tasks matching ``where`` and the matching rows that cannot be read, by id."""
    sql = _TASK_COLUMNS + (f" WHERE {where}" if where else "") + " ORDER BY t.id"
    tasks: list[Task] = []
    unreadable: list[UnreadableTask] = []
    for row in conn.execute(sql, tuple(parameters)):
        try:
            tasks.append(_task_of(row))
        except ValueError as exc:  # pydantic's ValidationError, bad JSON included
            problems = list(problems_of(exc)) if isinstance(exc, ValidationError) else []
            problem = str(problems[0]) if problems else str(exc).splitlines()[0]
            unreadable.append(UnreadableTask(str(row[0]), str(row[2]), problem))
    return tasks, unreadable


def _task_of(row: sqlite3.Row | tuple[object, ...]) -> Task:
    task_id, group_id, name, proposal, observation_type, priority, ipp, index, request, status = row
    return Task.model_validate(
        {
            "id": str(task_id),
            "group_id": str(group_id),
            "name": name,
            "proposal": proposal,
            "observation_type": observation_type,
            "priority": priority,
            "ipp": ipp,
            "request_index": index,
            "request": Request.model_validate_json(str(request)),
            "status": TaskStatus.model_validate_json(str(status)),
        }
    )


def update_status(conn: sqlite3.Connection, task_id: str, status: TaskStatus) -> None:
    """Store a task's new status."""
    conn.execute(
        "UPDATE tasks SET state = ?, status = ? WHERE id = ?",
        (status.state.value, status.model_dump_json(), int(task_id)),
    )


def replace_schedule(
    conn: sqlite3.Connection, entries: Sequence[PlannedSlot], replace_from: datetime
) -> None:
    """Drop entries starting at or after ``replace_from``; insert ``entries``."""
    conn.execute("DELETE FROM schedule WHERE start >= ?", (replace_from.timestamp(),))
    conn.executemany(
        "INSERT INTO schedule (task_id, start, end) VALUES (?, ?, ?)",
        [(int(e.task_id), e.start.timestamp(), e.end.timestamp()) for e in entries],
    )


def select_schedule(
    conn: sqlite3.Connection, start: datetime | None, end: datetime | None
) -> list[PlannedSlot]:
    """Entries overlapping ``[start, end)``, by start."""
    low = start.timestamp() if start else float("-inf")
    high = end.timestamp() if end else float("inf")
    rows = conn.execute(
        "SELECT task_id, start, end FROM schedule WHERE end > ? AND start < ? ORDER BY start, task_id",
        (low, high),
    )
    return [
        PlannedSlot(str(task_id), datetime.fromtimestamp(s, UTC), datetime.fromtimestamp(e, UTC))
        for task_id, s, e in rows
    ]
