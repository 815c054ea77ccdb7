"""Debian's Chromium driven by Playwright, as the browser tests (console, archive) and benchmarks use it.

Playwright's own browser download cannot be reached here, so it drives /usr/bin/chromium
(``make system-deps`` installs it). The flags keep Chromium off the network: without them it
tries Google's hosts at every start and the closed network refuses those connections.

The fixtures :func:`browser` (a headless Chromium per test; skipped without Chromium except under
CI=true) and :func:`page` (a fresh context; the test fails on an uncaught script error) are
shared by importing them into a ``conftest.py``::

    from nightcrew.testing.browser import browser, page  # noqa: F401 - fixtures
"""

from __future__ import annotations

import os
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path

import pytest
from playwright.async_api import Browser, Page, async_playwright

__all__ = ["CHROMIUM", "CHROMIUM_FLAGS", "browser", "chromium_missing", "launch_chromium", "page"]

CHROMIUM = Path("/usr/bin/chromium")
CHROMIUM_FLAGS = [
    "--no-sandbox",  # tests run as root, where Chromium's sandbox refuses to start
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]


def chromium_missing() -> str | None:
    """Why the browser tests cannot run here, or None; never a reason to skip when CI=true."""
    if CHROMIUM.exists():
        return None
    reason = f"{CHROMIUM} is missing: install Debian's chromium (make system-deps)"
    if os.environ.get("CI") == "true":
        raise RuntimeError(reason + " - CI must have it")
    return reason


@asynccontextmanager
async def launch_chromium() -> AsyncIterator[Browser]:
    """Headless Chromium with a fresh profile (Playwright gives every launch a new user-data-dir)."""
    async with async_playwright() as playwright:
        browser = await playwright.chromium.launch(
            executable_path=str(CHROMIUM), headless=True, args=CHROMIUM_FLAGS
        )
        try:
            yield browser
        finally:
            await browser.close()


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
    """A page in a fresh context; the test fails if the page's scripts threw an uncaught error."""
    context = await browser.new_context(viewport={"width": 1280, "height": 800})
    context.set_default_timeout(20_000)
    opened = await context.new_page()
    errors: list[str] = []
    opened.on("pageerror", lambda error: errors.append(str(error)))
    yield opened
    await context.close()
    assert not errors, f"uncaught script errors in the page: {errors}"
