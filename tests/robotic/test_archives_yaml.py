"""The YAML file archive: reload on change, keep states, refuse bad edits without losing tasks."""

from __future__ import annotations

import asyncio
import os
from datetime import UTC, datetime, timedelta
from pathlib import Path

import pytest
import yaml

from nightcrew.clock import AcceleratedClock
from nightcrew.robotic.archives import TaskChange, YamlTaskArchive
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import InvalidTaskError, TaskNotFoundError, TaskProgress, TaskState
from tests.robotic.test_archives_sqlite import NIGHT, ManualClock
from tests.robotic.test_tasks_model import valid_group_data


def _write(path: Path, groups: object) -> None:
    path.write_text(yaml.safe_dump(groups))
    # Some file systems keep mtime in whole seconds: move it on so every write is seen as one.
    stamp = path.stat().st_mtime_ns + 2_000_000_000
    os.utime(path, ns=(stamp, stamp))


def _second_group() -> dict[str, object]:
    data = valid_group_data()
    data["name"] = "second"
    data["requests"] = data["requests"][1:]
    return data


async def test_the_file_is_reloaded_when_it_changes_and_states_survive(tmp_path: Path) -> None:
    path = tmp_path / "tasks.yaml"
    _write(path, [valid_group_data()])
    clock = ManualClock(NIGHT)
    changes: list[TaskChange] = []
    async with YamlTaskArchive(path, clock=clock, poll_interval=0) as archive:
        archive.add_listener(changes.append)
        assert [t.id for t in await archive.list_tasks()] == ["m15 photometry/0", "m15 photometry/1"]
        await archive.mark_started("m15 photometry/0")
        assert not await archive.check_for_changes()  # nothing changed
        os.utime(path)  # touched only: same content
        assert not await archive.check_for_changes()

        edited = valid_group_data()
        edited["requests"][1]["configurations"][0]["instrument_configs"][0]["exposure_count"] = 20
        _write(path, {"request_groups": [edited, _second_group()]})
        assert await archive.check_for_changes()
        assert changes[-1] == TaskChange(frozenset({"m15 photometry/1", "second/0"}))
        running = await archive.get_task("m15 photometry/0")
        assert running.state is TaskState.RUNNING  # unchanged request: state kept
        updated = await archive.get_task("m15 photometry/1")
        assert updated.request.configurations[0].instrument_configs[0].exposure_count == 20

        _write(path, [_second_group()])  # the first group is gone
        assert await archive.check_for_changes()
        assert changes[-1] == TaskChange(frozenset({"m15 photometry/0", "m15 photometry/1"}))
        with pytest.raises(TaskNotFoundError, match="no task 'm15 photometry/0'"):
            await archive.get_task("m15 photometry/0")


async def test_a_bad_edit_keeps_the_last_good_tasks(tmp_path: Path) -> None:
    path = tmp_path / "tasks.yaml"
    _write(path, [valid_group_data()])
    async with YamlTaskArchive(path, clock=ManualClock(NIGHT), poll_interval=0) as archive:
        broken = valid_group_data()
        broken["requests"][0]["windows"][0]["end"] = "2026-11-10T12:00:00Z"
        _write(path, [_second_group(), broken, _second_group()])
        assert not await archive.check_for_changes()
        error = archive.last_error
        assert error is not None
        assert [str(p) for p in error.problems] == [
            "[1].requests[0].windows[0].end: must be after start (2026-11-10T17:50:00+00:00)",
            "[2].name: another group is called 'second'",
        ]
        assert (
            len(await archive.list_tasks()) == 2 and (await archive.list_tasks())[0].name == "m15 photometry"
        )
        _write(path, [_second_group()])
        assert await archive.check_for_changes() and archive.last_error is None
    _write(path, {"tasks": []})
    with pytest.raises(InvalidTaskError, match="expected a list of request groups"):
        await YamlTaskArchive(path, poll_interval=0).open()


async def test_polling_on_the_clock_picks_up_an_edit(tmp_path: Path) -> None:
    path = tmp_path / "tasks.yaml"
    _write(path, [])
    fast = AcceleratedClock(NIGHT, speed=1000.0)
    heard = asyncio.Event()
    async with YamlTaskArchive(path, clock=fast, poll_interval=5.0) as archive:
        archive.add_listener(lambda change: heard.set())
        assert await archive.list_tasks() == []
        _write(path, [valid_group_data()])
        await asyncio.wait_for(heard.wait(), timeout=5.0)
        assert len(await archive.list_tasks()) == 2


async def test_states_schedule_and_expiry_in_memory(tmp_path: Path) -> None:
    path = tmp_path / "tasks.yaml"
    _write(path, [valid_group_data()])
    clock = ManualClock(NIGHT)
    async with YamlTaskArchive(path, clock=clock, poll_interval=0) as archive:
        a, b = "m15 photometry/0", "m15 photometry/1"
        entry = PlannedSlot(b, NIGHT, NIGHT + timedelta(minutes=5))
        await archive.write_schedule([entry], replace_from=NIGHT)
        assert await archive.read_schedule() == [entry]
        assert (await archive.get_task(b)).state is TaskState.SCHEDULED
        await archive.mark_started(b)
        await archive.mark_failed(b, "camera error", TaskProgress(exposures_done=((4,),)))
        assert (await archive.get_task(b)).status.progress.total_exposures == 4
        assert [t.id for t in await archive.get_schedulable_tasks()] == [a, b]  # FAILED: may retry
        clock.unix = datetime(2026, 11, 11, 6, tzinfo=UTC).timestamp()
        assert await archive.get_schedulable_tasks() == []
        assert {t.state for t in await archive.list_tasks()} == {TaskState.WINDOW_EXPIRED}
        assert await archive.read_schedule(start=NIGHT + timedelta(minutes=5)) == []
