"""A WebSocket that drops: the page says so, reconnects by itself and is live again."""

from __future__ import annotations

from playwright.async_api import Page, expect

from nightcrew.modules.sim import SimFocuser

from .cutter import Cutter
from .observatory import Observatory, login


async def test_page_reconnects_after_the_connection_drops(page: Page, observatory: Observatory) -> None:
    async with Cutter(observatory.console.port if observatory.console else 0) as cutter:
        await login(page, f"http://127.0.0.1:{cutter.port}/")
        await expect(page.locator("body")).to_have_attribute("data-live", "open")
        cutter.cut()
        banner = page.locator("#live-banner")
        await expect(banner).to_contain_text("Live connection lost")
        await expect(banner).to_contain_text("The live connection is back")
        await expect(page.locator("body")).to_have_attribute("data-live", "open")
        # Live again: a module starting now appears in the list.
        await observatory.start(SimFocuser, "focuser2", focus=20.0, best_focus=21.0)
        await expect(page.locator("#module-list li[data-module='focuser2']")).to_be_visible()
