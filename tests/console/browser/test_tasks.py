"""The Tasks page and robotic start/stop in Chromium, on a real SQLite archive with a real scheduler
and mastermind: list, add from the form (valid and invalid) and as YAML, cancel, why not tonight;
an operator changes, a viewer only sees."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import pytest
from playwright.async_api import Page, expect

from nightcrew.interfaces import IRoboticScheduler, Plan, PlannedTask, UnplannedTask
from nightcrew.modules import Module
from nightcrew.modules.robotic import SchedulerModule
from nightcrew.modules.robotic.mastermind import Mastermind
from nightcrew.robotic import samples
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.tasks import TaskState, load_request_group_file

from .observatory import EPOCH, VIEWER, Observatory, login

ARCHIVE_CLASS = "nightcrew.robotic.archives.SqliteTaskArchive"
M31 = Path(samples.__file__).parent / "m31-andromeda-galaxy.yaml"


@pytest.fixture
async def database(tmp_path: Path) -> Path:
    return tmp_path / "tasks.sqlite"


@pytest.fixture
async def observatory(database: Path) -> AsyncIterator[Observatory]:
    """Devices, a scheduler planning from the task database, a stopped mastermind, and a console
    whose YAML names the same database."""
    obs = Observatory()
    archive = SqliteTaskArchive(database, clock=obs.clock, poll_interval=0)  # the scheduler's
    await archive.open()
    try:
        await obs.start_devices()
        await obs.start(SchedulerModule, "scheduler", archive=archive, store=archive, time_limit_s=2.0)
        description = {"class": ARCHIVE_CLASS, "path": str(database), "poll_interval": 0}
        await obs.start(
            Mastermind,
            "mastermind",
            archive=description,
            runner=TaskRunner(scripts={}),
            weather=None,
            autostart=False,
            poll_interval=60.0,  # it has nothing to do: it need not look often
        )
        await obs.start_console(tasks=description)
        yield obs
    finally:
        await obs.close()
        await archive.close()


async def stored(database: Path) -> dict[str, Any]:
    """The tasks in the database by name, as another process reads them."""
    async with SqliteTaskArchive(database, poll_interval=0) as archive:
        return {task.name: task for task in await archive.list_tasks()}


def utc_input(value: str) -> datetime:
    """The time in a datetime-local field of the form (UTC)."""
    return datetime.fromisoformat(value).replace(tzinfo=UTC)


async def fill_form(page: Page, **values: str) -> None:
    for field, value in values.items():
        await page.fill(f"#task-{field}", value)


async def test_an_operator_lists_adds_and_cancels_tasks_and_sees_why_one_is_not_planned(
    page: Page, observatory: Observatory, database: Path
) -> None:
    await login(page, observatory.url)
    await page.click("#nav-tasks")
    await expect(page.locator("#tasks-summary")).to_contain_text("0 tasks")
    # The defaults come from the request format's schema; the window is tonight on the clock.
    await expect(page.locator("#task-max-airmass")).to_have_value("2")
    await expect(page.locator("#task-min-lunar-distance")).to_have_value("30")
    await expect(page.locator("#task-window-start")).not_to_have_value("")
    start = utc_input(await page.input_value("#task-window-start"))
    assert datetime.fromisoformat(EPOCH) <= start <= observatory.clock.now()
    assert utc_input(await page.input_value("#task-window-end")) == start + timedelta(hours=12)

    await fill_form(
        page, **{"name": "Pleiades", "proposal": "open clusters", "telescope-class": "0m4", "target": "M45"}
    )
    await fill_form(
        page, ra="56.75", dec="24.12", **{"exposure-time": "60", "exposure-count": "3", "filter": "V"}
    )
    await page.click("#task-add")
    await expect(page.locator("#task-message")).to_have_text("added “Pleiades”: task 1")
    row = page.locator("#tasks-table tr[data-task='1']")
    await expect(row.locator("td.name")).to_contain_text("Pleiades")
    pleiades = (await stored(database))["Pleiades"]
    [configuration] = pleiades.request.configurations
    assert configuration.target is not None and configuration.target.ra == 56.75
    assert configuration.instrument_configs[0].optical_elements == {"filter": "V"}

    # The scheduler plans it: its next planned time shows.
    scheduler = observatory.modules["scheduler"]
    assert isinstance(scheduler, SchedulerModule)
    await expect(row.locator("td.tonight time")).to_be_visible()
    plan = await scheduler.get_plan()
    assert plan is not None
    [slot] = [s for s in plan.slots if s.task_id == "1"]
    await expect(row.locator("td.tonight time")).to_have_attribute("datetime", slot.start.isoformat())

    # Invalid: a bound of the schema is checked in the page, nothing is sent.
    await fill_form(page, name="Southern field", target="NGC 2070", ra="400", dec="-80")
    await page.click("#task-add")
    ra_error = page.locator("label[data-path='requests[0].configurations[0].target.ra'] .field-error")
    await expect(ra_error).not_to_be_empty()
    # Invalid: what only the model knows (the window's order) comes back named, at its field.
    await fill_form(page, ra="120", **{"window-end": "2024-01-15T21:00"})
    await page.click("#task-add")
    end_error = page.locator("label[data-path='requests[0].windows[0].end'] .field-error")
    await expect(end_error).to_have_text(f"must be after start ({start.isoformat()})")
    await expect(page.locator("#task-message")).to_contain_text("InvalidTaskError")
    await expect(ra_error).to_be_empty()
    assert list(await stored(database)) == ["Pleiades"]

    # Fixed, it is added; never above the horizon here, the scheduler leaves it out: why?
    await fill_form(page, **{"window-end": "2024-01-16T06:00"})
    await page.click("#task-add")
    await expect(page.locator("#task-message")).to_have_text("added “Southern field”: task 2")
    southern = page.locator("#tasks-table tr[data-task='2']")
    await expect(southern.locator("td.tonight")).to_contain_text("not planned")
    await southern.locator("details.why summary").click()
    reasons = {u.task_id: u.reason for u in ((await scheduler.get_plan()) or plan).unplanned}
    await expect(southern.locator("details.why .reason")).to_have_text(reasons.get("2", "no reason recorded"))

    # A whole group as YAML, as in a task file.
    await page.click("#task-raw summary")
    await page.click("#task-raw-from-form")  # the form's group as a start
    await expect(page.locator("#task-raw-text")).to_have_value(re.compile(r'"name": "Southern field"'))
    await page.fill("#task-raw-text", M31.read_text())
    await page.click("#task-raw-add")
    await expect(page.locator("#task-message")).to_have_text("added “M31 Andromeda galaxy”: task 3")
    await expect(page.locator("#tasks-table tr[data-task='3']")).to_be_visible()

    # Cancel, with a reason.
    await southern.locator("button.cancel").click()
    await southern.locator("input.cancel-reason").fill("too far south")
    await southern.locator("button.cancel-confirm").click()
    await expect(southern).to_have_attribute("data-state", "CANCELED")
    await expect(southern.locator("td.state")).to_contain_text("too far south (olga, console)")
    await expect(southern.locator("button.cancel")).to_have_count(0)
    assert (await stored(database))["Southern field"].state is TaskState.CANCELED


class RecordedPlan(Module, IRoboticScheduler):
    """A scheduler's plan as given: one task planned, one left out with the reason it recorded."""

    def __init__(self, *, plan: Plan, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.plan = plan

    async def get_plan(self) -> Plan | None:
        return self.plan


async def test_why_not_tonight_shows_the_reason_the_scheduler_recorded(page: Page, database: Path) -> None:
    obs = Observatory()
    try:
        await obs.start_console(tasks={"class": ARCHIVE_CLASS, "path": str(database), "poll_interval": 0})
        await login(page, obs.url)
        await page.click("#nav-tasks")
        for name, dec in (("Pleiades", "24.12"), ("Southern field", "-80")):
            await fill_form(page, name=name, proposal="p", target=name, ra="56.75", dec=dec)
            await fill_form(page, **{"telescope-class": "0m4", "exposure-time": "60"})
            await page.click("#task-add")
            await expect(page.locator("#task-message")).to_contain_text(f"added “{name}”")
        now = obs.clock.now()
        start, end = (
            datetime.fromisoformat("2024-01-15T23:00:00+00:00"),
            datetime.fromisoformat("2024-01-15T23:10:00+00:00"),
        )
        reason = "never above the airmass limit 2.0 (highest: 8.9 at 23:40)"
        plan = Plan(
            planned_at=now,
            night_start=now,
            night_end=end,
            solver="mip",
            status="optimal",
            objective=2.0,
            bound=2.0,
            gap=0.0,
            wall_time_s=0.1,
            slots=(PlannedTask("1", start, end, 1.0, "Pleiades"),),
            unplanned=(UnplannedTask("2", reason, "Southern field"),),
        )
        await obs.start(RecordedPlan, "scheduler", plan=plan)
        southern = page.locator("#tasks-table tr[data-task='2']")
        await expect(page.locator("#tasks-table tr[data-task='1'] td.tonight")).to_contain_text(
            "2024-01-15 23:00 \N{EN DASH} 23:10"
        )
        await southern.locator("details.why summary").click()
        await expect(southern.locator("details.why .reason")).to_have_text(reason)
    finally:
        await obs.close()


async def test_an_operator_starts_and_stops_robotic_mode(page: Page, observatory: Observatory) -> None:
    mastermind = observatory.modules["mastermind"]
    assert isinstance(mastermind, Mastermind)
    await login(page, observatory.url)
    await page.click("#module-list li[data-module='mastermind'] a")
    mode = page.locator("#mm-mode")
    await expect(mode).to_have_text("stopped")
    await expect(page.locator("#mm-stop")).to_be_disabled()  # nothing to stop
    await page.click("#mm-start")
    await expect(mode).to_have_text("running")
    await expect(page.locator("#mm-message")).to_have_text("robotic mode started")
    await expect(page.locator("#mm-start")).to_be_disabled()
    assert await mastermind.is_running()
    await expect(page.locator("#mm-action")).not_to_have_text("stopped")  # the robotic status follows
    await page.click("#mm-stop")
    await expect(mode).to_have_text("stopped")
    assert not await mastermind.is_running()
    await expect(page.locator("#mm-action")).to_have_text("stopped")


async def test_a_viewer_sees_tasks_and_robotic_mode_but_the_console_refuses_changes(
    page: Page, observatory: Observatory, database: Path
) -> None:
    async with SqliteTaskArchive(database, poll_interval=0) as archive:
        await archive.add_request_group(load_request_group_file(M31))
    await login(page, observatory.url, VIEWER)
    await page.click("#nav-tasks")
    row = page.locator("#tasks-table tr[data-task='1']")
    await expect(row.locator("td.name")).to_contain_text("M31 Andromeda galaxy")
    await expect(row.locator("button.cancel")).to_be_disabled()
    await expect(page.locator("#task-add")).to_be_disabled()
    await expect(page.locator("#task-raw-add")).to_be_disabled()

    await page.click("#module-list li[data-module='mastermind'] a")
    await expect(page.locator("#mm-mode")).to_have_text("stopped")
    await expect(page.locator("#mm-start")).to_be_disabled()
    await expect(page.locator("#mm-stop")).to_be_disabled()

    # Past the page: the server refuses the viewer's session.
    statuses = await page.evaluate(
        """async () => {
            const session = await (await fetch("/api/session")).json();
            const post = (path, body) => fetch(path, {method: "POST", body: JSON.stringify(body),
                headers: {"Content-Type": "application/json", "X-CSRF-Token": session.csrf_token}});
            return [
                (await post("/api/call", {module: "mastermind", method: "start", args: []})).status,
                (await post("/api/tasks/1/cancel", {})).status,
                (await post("/api/tasks", {name: "x"})).status,
            ];
        }"""
    )
    assert statuses == [403, 403, 403]
    mastermind = observatory.modules["mastermind"]
    assert isinstance(mastermind, Mastermind) and not await mastermind.is_running()
    tasks = await stored(database)
    assert list(tasks) == ["M31 Andromeda galaxy"]
    assert tasks["M31 Andromeda galaxy"].state is TaskState.PENDING
