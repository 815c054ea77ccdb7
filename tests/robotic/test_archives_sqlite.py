"""The SQLite archive on a real database file: persistence, transactions, states, schedule."""

from __future__ import annotations

import logging
import sqlite3
from datetime import UTC, datetime, timedelta
from pathlib import Path

import pytest

from nightcrew.clock import Clock
from nightcrew.errors import InvalidArgumentError, ModuleError
from nightcrew.robotic.archives import SqliteTaskArchive, TaskChange, _sqlite_schema
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import (
    InvalidTransitionError,
    TaskError,
    TaskNotFoundError,
    TaskProgress,
    TaskState,
    parse_request_group,
)
from tests.robotic.test_tasks_model import valid_group_data

NIGHT = datetime(2026, 11, 10, 18, tzinfo=UTC)


class ManualClock(Clock):
    """A clock that stands still until a test moves it."""

    def __init__(self, now: datetime) -> None:
        self.unix = now.timestamp()

    @property
    def speed(self) -> float:
        return 1.0

    def time(self) -> float:
        return self.unix

    def advance(self, seconds: float) -> None:
        self.unix += seconds


@pytest.fixture
def clock() -> ManualClock:
    return ManualClock(NIGHT)


def _archive(path: Path, clock: Clock) -> SqliteTaskArchive:
    return SqliteTaskArchive(path, clock=clock, poll_interval=0)


async def test_tasks_persist_across_reopen(tmp_path: Path, clock: ManualClock) -> None:
    path = tmp_path / "tasks.sqlite"
    group = parse_request_group(valid_group_data())
    async with _archive(path, clock) as archive:
        tasks = await archive.add_request_group(group)
        assert [(t.id, t.group_id, t.request_index, t.state) for t in tasks] == [
            ("1", "1", 0, TaskState.PENDING),
            ("2", "1", 1, TaskState.PENDING),
        ]
        await archive.mark_started("1")
        progress = TaskProgress.nothing_done(tasks[0].request).with_exposures(tasks[0].request, 0, 0, 2)
        await archive.mark_failed("1", "the roof closed", progress)
    async with _archive(path, clock) as reopened:
        again = await reopened.get_task("1")
        assert again.request == group.requests[0] and again.name == group.name and again.ipp == 1.5
        assert (again.state, again.status.reason) == (TaskState.FAILED, "the roof closed")
        assert again.status.progress.count(0, 0) == 2
        assert again.status.started_at == NIGHT
        assert [t.id for t in await reopened.list_tasks(states=[TaskState.PENDING])] == ["2"]
    with sqlite3.connect(path) as conn:
        assert conn.execute("SELECT version FROM schema_version").fetchall() == [(1,)]


async def test_a_failure_mid_add_stores_nothing(
    tmp_path: Path, clock: ManualClock, monkeypatch: pytest.MonkeyPatch
) -> None:
    inserted: list[int] = []
    real_insert = _sqlite_schema.insert_task

    def insert_then_fail(conn: sqlite3.Connection, group_id: int, index: int, request: object) -> int:
        if inserted:
            raise sqlite3.OperationalError("disk I/O error")  # the second request's row
        inserted.append(real_insert(conn, group_id, index, request))  # type: ignore[arg-type]
        return inserted[-1]

    async with _archive(tmp_path / "tasks.sqlite", clock) as archive:
        monkeypatch.setattr(_sqlite_schema, "insert_task", insert_then_fail)
        with pytest.raises(sqlite3.OperationalError, match="disk I/O error"):
            await archive.add_request_group(parse_request_group(valid_group_data()))
        assert inserted == [1]  # the first task was written, then rolled back
        assert await archive.list_tasks() == []
        monkeypatch.undo()
        tasks = await archive.add_request_group(parse_request_group(valid_group_data()))
        assert len(tasks) == 2
    with sqlite3.connect(tmp_path / "tasks.sqlite") as conn:
        assert conn.execute("SELECT count(*) FROM request_groups").fetchone() == (1,)


async def test_states_follow_the_table_and_a_refused_change_stores_nothing(
    tmp_path: Path, clock: ManualClock
) -> None:
    async with _archive(tmp_path / "t.sqlite", clock) as archive:
        task = (await archive.add_request_group(parse_request_group(valid_group_data())))[1]
        with pytest.raises(InvalidTransitionError, match="a PENDING task cannot become COMPLETED"):
            await archive.mark_finished(task.id, TaskProgress())
        with pytest.raises(InvalidTransitionError, match="only be recorded while RUNNING"):
            await archive.record_progress(task.id, TaskProgress())
        assert (await archive.get_task(task.id)).state is TaskState.PENDING
        clock.advance(60)
        running = await archive.mark_started(task.id)
        assert running.status.started_at == NIGHT + timedelta(seconds=60)
        one = TaskProgress(exposures_done=((1,),))
        assert (await archive.record_progress(task.id, one)).status.progress == one
        with pytest.raises(InvalidArgumentError, match="progress has"):
            await archive.mark_finished(task.id, TaskProgress(exposures_done=((1, 1),)))
        done = await archive.mark_finished(task.id, one)
        assert done.state is TaskState.COMPLETED and done.status.finished_at == NIGHT + timedelta(seconds=60)
        with pytest.raises(InvalidTransitionError, match="a COMPLETED task cannot become CANCELED"):
            await archive.cancel(task.id, "too late")
        canceled = await archive.cancel("1", "not needed")
        assert (canceled.state, canceled.status.reason) == (TaskState.CANCELED, "not needed")
        for missing in ("99", "m13/1"):
            with pytest.raises(TaskNotFoundError, match=f"no task '{missing}'"):
                await archive.get_task(missing)


async def test_schedulable_tasks_expire_after_their_last_window(tmp_path: Path, clock: ManualClock) -> None:
    changes: list[TaskChange] = []
    async with _archive(tmp_path / "t.sqlite", clock) as archive:
        archive.add_listener(changes.append)
        await archive.add_request_group(parse_request_group(valid_group_data()))
        assert [t.id for t in await archive.get_schedulable_tasks()] == ["1", "2"]
        await archive.mark_started("2")
        clock.unix = datetime(2026, 11, 11, 5, tzinfo=UTC).timestamp()  # the windows' end
        assert await archive.get_schedulable_tasks() == []
        assert (await archive.get_task("1")).state is TaskState.WINDOW_EXPIRED
        assert (await archive.get_task("2")).state is TaskState.RUNNING  # running tasks may overrun
    assert changes == [
        TaskChange(frozenset({"1", "2"})),
        TaskChange(frozenset({"2"})),
        TaskChange(frozenset({"1"})),
    ]


async def test_the_schedule_is_written_read_and_sets_states(tmp_path: Path, clock: ManualClock) -> None:
    async with _archive(tmp_path / "t.sqlite", clock) as archive:
        await archive.add_request_group(parse_request_group(valid_group_data()))
        first = PlannedSlot("1", NIGHT, NIGHT + timedelta(minutes=10))
        second = PlannedSlot("2", NIGHT + timedelta(minutes=10), NIGHT + timedelta(minutes=15))
        await archive.write_schedule([second, first], replace_from=NIGHT)
        assert await archive.read_schedule() == [first, second]
        assert [t.state for t in await archive.list_tasks()] == [TaskState.SCHEDULED] * 2
        assert await archive.read_schedule(start=NIGHT + timedelta(minutes=12)) == [second]
        assert await archive.read_schedule(end=NIGHT + timedelta(minutes=10)) == [first]
        # A new plan from minute 5 on keeps the entry that started before and drops task 2.
        await archive.write_schedule([], replace_from=NIGHT + timedelta(minutes=5))
        assert await archive.read_schedule() == [first]
        assert [t.state for t in await archive.list_tasks()] == [TaskState.SCHEDULED, TaskState.PENDING]
        # An unknown task spoils the whole schedule: nothing changes.
        with pytest.raises(TaskNotFoundError, match="no task '7'"):
            await archive.write_schedule(
                [second, PlannedSlot("7", NIGHT, NIGHT + timedelta(1))], replace_from=NIGHT
            )
        assert await archive.read_schedule() == [first]


async def test_listeners_hear_other_processes_and_survive_broken_listeners(
    tmp_path: Path, clock: ManualClock, caplog: pytest.LogCaptureFixture
) -> None:
    heard: list[TaskChange] = []

    async def async_listener(change: TaskChange) -> None:
        heard.append(change)

    def broken_listener(change: TaskChange) -> None:
        raise RuntimeError("listener bug")

    path = tmp_path / "shared.sqlite"
    async with _archive(path, clock) as robotic, _archive(path, clock) as command_line:
        robotic.add_listener(broken_listener)
        robotic.add_listener(async_listener)
        assert not await robotic.check_for_changes()
        with caplog.at_level(logging.ERROR):
            await command_line.add_request_group(parse_request_group(valid_group_data()))
            assert await robotic.check_for_changes()
        assert heard == [TaskChange()]
        assert "listener bug" in caplog.text
        robotic.remove_listener(broken_listener)
        await robotic.mark_started("1")
        assert heard[-1] == TaskChange(frozenset({"1"}))


async def test_the_poll_loop_notices_changes_on_the_clock(tmp_path: Path) -> None:
    from nightcrew.clock import AcceleratedClock

    fast = AcceleratedClock(NIGHT, speed=1000.0)
    path = tmp_path / "shared.sqlite"
    heard: list[TaskChange] = []
    async with SqliteTaskArchive(path, clock=fast, poll_interval=5.0) as robotic:
        robotic.add_listener(heard.append)
        async with _archive(path, fast) as other:
            await other.add_request_group(parse_request_group(valid_group_data()))
        await fast.sleep(20.0)  # 20 ms of wall time: four polls
        assert heard == [TaskChange()]


async def test_a_newer_schema_and_a_closed_archive_are_refused(tmp_path: Path, clock: ManualClock) -> None:
    path = tmp_path / "t.sqlite"
    archive = _archive(path, clock)
    with pytest.raises(ModuleError, match="is not open"):
        await archive.list_tasks()
    await archive.open()
    await archive.close()
    await archive.close()  # twice is fine
    with sqlite3.connect(path) as conn:
        conn.execute("UPDATE schema_version SET version = 9")
    with pytest.raises(TaskError, match="schema version 9; this nightcrew knows 1"):
        await _archive(path, clock).open()
