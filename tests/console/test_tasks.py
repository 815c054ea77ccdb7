"""The console's task routes on a real SQLite archive, with a real scheduler planning from it."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from datetime import datetime
from pathlib import Path
from typing import Any

import pytest

from nightcrew.events import TasksChangedEvent
from nightcrew.interfaces import ModuleState
from nightcrew.modules import Module
from nightcrew.modules.console import WebConsole
from nightcrew.modules.robotic import SchedulerModule
from nightcrew.robotic import samples
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.tasks import TaskState, request_group_schema
from nightcrew.testing import EPOCH

from .conftest import (
    OPERATOR,
    OPERATOR_PASSWORD,
    PATIENCE,
    VIEWER,
    VIEWER_PASSWORD,
    ApiClient,
    Observatory,
    eventually,
)

ARCHIVE_CLASS = "nightcrew.robotic.archives.SqliteTaskArchive"


def group(name: str, ra: float, dec: float, **changes: Any) -> dict[str, Any]:
    """A request group observable the night of the test clock (from 2024-01-15 22:00 UTC)."""
    data: dict[str, Any] = {
        "name": name,
        "proposal": "console-tests",
        "priority": 2,
        "requests": [
            {
                "location": {"telescope_class": "0m4"},
                "windows": [{"start": "2024-01-15T21:00:00Z", "end": "2024-01-16T05:00:00Z"}],
                "configurations": [
                    {
                        "type": "EXPOSE",
                        "target": {"name": name, "ra": ra, "dec": dec},
                        "instrument_configs": [{"exposure_time": 60, "exposure_count": 3}],
                    }
                ],
            }
        ],
    }
    data.update(changes)
    return data


class Listener(Module):
    """Keeps the TasksChangedEvents it hears."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.heard: asyncio.Queue[TasksChangedEvent] = asyncio.Queue()

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(TasksChangedEvent, self.on_tasks_changed)

    async def on_tasks_changed(self, event: TasksChangedEvent, sender: str) -> None:
        self.heard.put_nowait(event)


@pytest.fixture
async def console(tmp_path: Path, observatory: Observatory) -> WebConsole:
    """A console with the task archive its YAML would describe."""
    tasks = {"class": ARCHIVE_CLASS, "path": str(tmp_path / "tasks.sqlite"), "poll_interval": 0}
    return await observatory.start_console(tasks=tasks)


@pytest.fixture
async def operator(console: WebConsole, clients: Callable[[str], ApiClient]) -> ApiClient:
    client = clients(console.url)
    assert (await client.login(OPERATOR, OPERATOR_PASSWORD))[0] == 200
    return client


async def test_tasks_show_their_next_planned_time_and_why_they_are_left_out(
    observatory: Observatory, operator: ApiClient, archive: SqliteTaskArchive
) -> None:
    """``archive``: the same file opened for the scheduler, as another process would."""
    listener = await observatory.start(Listener, "listener")
    status, added = await operator.post("/api/tasks", group("Pleiades", 56.75, 24.12))
    assert status == 201, added
    [pleiades] = added["tasks"]
    assert pleiades["state"] == "PENDING" and pleiades["name"] == "Pleiades"
    assert pleiades["configurations"] == [{"type": "EXPOSE", "target": "Pleiades"}]
    heard = await asyncio.wait_for(listener.heard.get(), PATIENCE)
    assert heard.ids == (pleiades["id"],) and heard.change == "added"
    # Never above the horizon at 51.6° north: the scheduler leaves it out.
    status, added = await operator.post("/api/tasks", group("Southern field", 120.0, -80.0))
    [southern] = added["tasks"]

    scheduler = await observatory.start(
        SchedulerModule, "scheduler", archive=archive, store=archive, time_limit_s=2.0
    )

    async def rows() -> dict[str, dict[str, Any]]:
        return {row["id"]: row for row in (await operator.get("/api/tasks"))[1]["tasks"]}

    async def planned() -> bool:
        return (await rows())[pleiades["id"]]["next_start"] is not None

    await eventually(planned, "the Pleiades in the plan")
    plan = await scheduler.get_plan()
    assert plan is not None
    status, listing = await operator.get("/api/tasks")
    assert status == 200 and listing["plan"] == {
        "module": "scheduler",
        "planned_at": plan.planned_at.isoformat(),
    }
    by_id = {row["id"]: row for row in listing["tasks"]}
    assert [row["id"] for row in listing["tasks"]] == [southern["id"], pleiades["id"]]  # newest first
    [slot] = [s for s in plan.slots if s.task_id == pleiades["id"]]
    assert by_id[pleiades["id"]]["next_start"] == slot.start.isoformat()
    assert by_id[pleiades["id"]]["why_not"] is None
    assert by_id[southern["id"]]["next_start"] is None
    reasons = {u.task_id: u.reason for u in plan.unplanned}
    assert by_id[southern["id"]]["why_not"] == reasons.get(southern["id"])  # None until it records one

    # Cancelled, it is planned no more, even by a plan made before.
    assert (await operator.post(f"/api/tasks/{pleiades['id']}/cancel", {}))[0] == 200
    row = (await rows())[pleiades["id"]]
    assert row["ended"] and row["next_start"] is None and row["why_not"] is None


async def test_a_group_is_validated_as_nightcrew_tasks_add_does_and_nothing_is_stored_on_error(
    console: WebConsole, operator: ApiClient
) -> None:
    bad = group("Pleiades", 400.0, 24.12, priority=0)
    bad["requests"][0]["windows"][0]["end"] = "2024-01-15T20:00:00Z"
    status, body = await operator.post("/api/tasks", bad)
    assert status == 400 and body["error"]["class"] == "InvalidTaskError"
    problems = {p["path"]: p["message"] for p in body["error"]["problems"]}
    assert problems == {
        "priority": "must be > 0",
        "requests[0].windows[0].end": "must be after start (2024-01-15T21:00:00+00:00)",
        "requests[0].configurations[0].target.ra": "must be < 360",
    }
    assert body["error"]["message"].endswith("(and 2 more problems)")
    assert console.task_archive is not None and await console.task_archive.list_tasks() == []

    # A task file's text, as for `nightcrew tasks add FILE`; a YAML error names its line.
    text = (Path(samples.__file__).parent / "m31-andromeda-galaxy.yaml").read_text()
    async with operator.http.post(
        operator.base + "/api/tasks",
        data=text.encode(),
        headers={"X-CSRF-Token": operator.csrf, "Content-Type": "application/yaml"},
    ) as response:
        assert response.status == 201
        assert [t["name"] for t in (await response.json())["tasks"]] == ["M31 Andromeda galaxy"]
    async with operator.http.post(
        operator.base + "/api/tasks",
        data=b"name: [unclosed\n",
        headers={"X-CSRF-Token": operator.csrf, "Content-Type": "application/yaml"},
    ) as response:
        error = (await response.json())["error"]
        assert response.status == 400 and error["problems"][0]["message"].startswith("line 2: ")
    async with operator.http.post(
        operator.base + "/api/tasks", data=b"name: x", headers={"X-CSRF-Token": operator.csrf}
    ) as response:
        assert response.status == 400
        assert "expected Content-Type application/json" in (await response.json())["error"]["message"]
    assert len(await console.task_archive.list_tasks()) == 1

    status, schema = await operator.get("/api/tasks/schema")
    assert status == 200 and schema == request_group_schema()


async def test_an_operator_cancels_and_the_scheduler_hears_of_it(
    observatory: Observatory, console: WebConsole, operator: ApiClient
) -> None:
    listener = await observatory.start(Listener, "listener")
    [task] = (await operator.post("/api/tasks", group("Pleiades", 56.75, 24.12)))[1]["tasks"]
    await asyncio.wait_for(listener.heard.get(), PATIENCE)  # added

    status, body = await operator.post(f"/api/tasks/{task['id']}/cancel", {"reason": "clouds all week"})
    assert status == 200
    assert body["task"]["state"] == "CANCELED" and body["task"]["ended"] is True
    assert body["task"]["reason"] == f"clouds all week ({OPERATOR}, console)"
    heard = await asyncio.wait_for(listener.heard.get(), PATIENCE)
    assert heard.ids == (task["id"],) and heard.change == "cancelled"
    assert console.task_archive is not None
    [stored] = await console.task_archive.list_tasks()
    assert stored.state is TaskState.CANCELED
    # Built from its description, the archive keeps the console's clock (a simulated night's time).
    assert stored.status.finished_at is not None
    assert datetime.fromisoformat(EPOCH) <= stored.status.finished_at <= observatory.clock.now()

    status, body = await operator.post(f"/api/tasks/{task['id']}/cancel", {})
    assert status == 409 and "cannot become CANCELED" in body["error"]["message"]
    status, body = await operator.post("/api/tasks/9999/cancel", {})
    assert status == 404 and body["error"]["class"] == "TaskNotFoundError"


async def test_a_viewer_sees_the_tasks_but_cannot_add_or_cancel(
    console: WebConsole, operator: ApiClient, clients: Callable[[str], ApiClient]
) -> None:
    [task] = (await operator.post("/api/tasks", group("Pleiades", 56.75, 24.12)))[1]["tasks"]
    viewer = clients(console.url)
    await viewer.login(VIEWER, VIEWER_PASSWORD)
    status, listing = await viewer.get("/api/tasks")
    assert status == 200 and [t["id"] for t in listing["tasks"]] == [task["id"]]
    status, body = await viewer.post("/api/tasks", group("M45", 56.75, 24.12))
    assert status == 403 and body["error"]["message"] == "a viewer may not add tasks"
    status, body = await viewer.post(f"/api/tasks/{task['id']}/cancel", {})
    assert status == 403 and body["error"]["message"] == "a viewer may not cancel tasks"
    assert console.task_archive is not None
    [stored] = await console.task_archive.list_tasks()
    assert stored.state is TaskState.PENDING


async def test_without_an_archive_there_is_no_tasks_page(
    observatory: Observatory, clients: Callable[[str], ApiClient]
) -> None:
    console = await observatory.start_console()
    client = clients(console.url)
    await client.login(OPERATOR, OPERATOR_PASSWORD)
    assert (await client.get("/api/config"))[1]["show_tasks"] is False
    status, body = await client.get("/api/tasks")
    assert status == 404 and body["error"]["class"] == "ConfigError"
