"""The Shell, Events and Status pages against the simulated observatory."""

from __future__ import annotations

import asyncio
from typing import Any

from playwright.async_api import Page, expect

from nightcrew.events import TestEvent
from nightcrew.interfaces import ModuleState
from nightcrew.modules import Module

from .observatory import Observatory, login


class Listener(Module):
    """Keeps the TestEvents it receives, with their senders."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.received: asyncio.Queue[tuple[TestEvent, str]] = asyncio.Queue()

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(TestEvent, self.on_test)

    async def on_test(self, event: TestEvent, sender: str) -> None:
        self.received.put_nowait((event, sender))


async def test_shell_completes_calls_and_shows_results_and_remote_errors(
    page: Page, observatory: Observatory
) -> None:
    await login(page, observatory.url)
    await page.click("#nav-shell")
    shell = page.locator("#shell-input")
    await shell.fill("fil")
    await shell.press("Tab")
    await expect(shell).to_have_value("filters.")
    await shell.press_sequentially("set_f")
    await shell.press("Tab")
    await expect(shell).to_have_value("filters.set_filter(")
    await expect(page.locator("#shell-hint")).to_have_text("filter_name: str")

    await shell.fill("filters.set_filter('R')")
    await shell.press("Enter")
    await expect(page.locator("#shell-output li").last.locator(".result")).to_have_text("done (no result)")
    assert await observatory.modules["filters"].get_filter() == "R"  # type: ignore[attr-defined]
    await shell.fill("filters.get_filter()")
    await shell.press("Enter")
    await expect(page.locator("#shell-output li").last.locator(".result.ok")).to_have_text("R")

    # A remote error keeps its class and names the module; a line that does not parse says why.
    await shell.fill("filters.set_filter('H-alpha')")
    await shell.press("Enter")
    error = page.locator("#shell-output li").last.locator(".result.error")
    await expect(error.locator(".error-class")).to_have_text("InvalidArgumentError")
    await expect(error).to_contain_text("from filters")
    await expect(error).to_contain_text("H-alpha")
    await shell.fill("filters.set_filter(")
    await shell.press("Enter")
    await expect(page.locator("#shell-output li").last.locator(".result.error")).to_contain_text(
        "InvalidArgumentError"
    )

    # History: Up brings back the lines typed before.
    await shell.press("ArrowUp")
    await expect(shell).to_have_value("filters.set_filter(")
    await shell.press("ArrowUp")
    await expect(shell).to_have_value("filters.set_filter('H-alpha')")


async def test_events_page_receives_and_sends_events(page: Page, observatory: Observatory) -> None:
    listener = await observatory.start(Listener, "listener")
    await login(page, observatory.url)
    await page.click("#nav-events")
    await listener.comm.send_event(TestEvent(message="hello from the listener"))
    row = page.locator("#events-list li[data-event='TestEvent'][data-sender='listener']")
    await expect(row).to_contain_text("message=hello from the listener")

    # Filters: by sender, then by a type nothing sent.
    await page.select_option("#events-sender", "listener")
    await expect(page.locator("#events-list li").first).to_have_attribute("data-sender", "listener")
    await page.select_option("#events-sender", "")
    await page.select_option("#events-type", "TestEvent")
    await expect(page.locator("#events-list li:not([data-event='TestEvent'])")).to_have_count(0)

    await page.select_option("#send-type", "TestEvent")
    await page.fill("#send-field-message", "hello from the browser")
    await page.click("#send-event")
    await expect(page.locator("#send-message")).to_have_text("TestEvent sent")
    while True:  # each wait is bounded; the listener gets only a few events
        event, sender = await asyncio.wait_for(listener.received.get(), 20)
        if event.message == "hello from the browser":
            break
    assert sender == "console"
    # The console's own event is in its list too (the bus does not echo it; the console adds it).
    sent = page.locator("#events-list li[data-sender='console']")
    await expect(sent).to_contain_text("message=hello from the browser")


async def test_status_page_shows_and_resets_an_error(page: Page, observatory: Observatory) -> None:
    focuser = observatory.modules["focuser"]
    await login(page, observatory.url)
    await page.click("#nav-status")
    row = page.locator("#status-table tr[data-module='focuser']")
    await expect(row.locator("td.state")).to_have_text("ready")
    await expect(row.locator("button.reset")).to_have_count(0)  # offered only for a module in error
    focuser.set_error("motor stalled at 24.8 mm")
    await expect(row.locator("td.state")).to_have_text("error")
    await expect(row.locator("td.error")).to_have_text("motor stalled at 24.8 mm")
    await expect(page.locator("#module-list li[data-module='focuser']")).to_have_attribute(
        "data-state", "error"
    )
    await row.locator("button.reset").click()
    await expect(page.locator("#status-message")).to_have_text("focuser: error reset, ready again")
    await expect(row.locator("td.state")).to_have_text("ready")
    assert focuser.state is ModuleState.READY
    version = await focuser.get_version()
    await expect(row.locator("td").nth(3)).to_have_text(version)


async def test_log_pane_filters_by_level_and_module(page: Page, observatory: Observatory) -> None:
    await login(page, observatory.url)
    await page.click("#module-list li[data-module='filters'] a")
    await page.select_option("#filter-select", "R")
    await page.click("#filter-set")
    records = page.locator("#log-list li")
    moving = records.filter(has_text="filters: motion status idle -> moving")
    await expect(moving.first).to_be_visible()
    await expect(moving.first.locator(".mod")).to_have_text("filters")
    await page.select_option("#log-module", "telescope")
    await expect(records.filter(has_text="filters:")).to_have_count(0)
    await page.select_option("#log-module", "filters")
    await expect(moving.first).to_be_visible()
    await page.select_option("#log-level", "WARNING")  # the motion records are INFO
    await expect(moving).to_have_count(0)
