"""Fixtures of the console's browser tests: a headless Chromium, pages that record script errors,
and a simulated observatory with a console."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest
from playwright.async_api import Browser, Page, expect

from .browser import chromium_missing, launch_chromium
from .observatory import Observatory

# Conditions in the page are awaited, never slept for; this bounds each wait on a busy machine.
expect.set_options(timeout=20_000)


@pytest.fixture
async def browser() -> AsyncIterator[Browser]:
    """A headless Chromium of its own per test; skips without Chromium except when CI=true."""
    reason = chromium_missing()
    if reason is not None:
        pytest.skip(reason)
    async with launch_chromium() as launched:
        yield launched


@pytest.fixture
async def page(browser: Browser) -> AsyncIterator[Page]:
    """A page in a fresh context; the test fails if the console's scripts threw an uncaught error."""
    context = await browser.new_context(viewport={"width": 1280, "height": 800})
    context.set_default_timeout(20_000)
    opened = await context.new_page()
    errors: list[str] = []
    opened.on("pageerror", lambda error: errors.append(str(error)))
    yield opened
    await context.close()
    assert not errors, f"uncaught script errors in the console: {errors}"


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    """The simulated devices and a console with default options."""
    obs = Observatory()
    try:
        await obs.start_devices()
        await obs.start_console()
        yield obs
    finally:
        await obs.close()
