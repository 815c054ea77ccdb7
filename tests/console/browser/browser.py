"""Debian's Chromium driven by Playwright, as the console's browser tests and benchmark use it.

Playwright's own browser download cannot be reached here, so it drives /usr/bin/chromium
(``make system-deps`` installs it). The flags keep Chromium off the network: without them it
tries Google's hosts at every start and the closed network refuses those connections.
"""

from __future__ import annotations

import os
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path

from playwright.async_api import Browser, async_playwright

__all__ = ["CHROMIUM", "CHROMIUM_FLAGS", "chromium_missing", "launch_chromium"]

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
