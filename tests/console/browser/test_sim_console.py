"""``nightcrew sim --console``: a new user watches the simulated night live in a browser.

The sim runs as its own process (as a user starts it); the test logs in with the one-time
account's password (given in NIGHTCREW_CONSOLE_PASSWORD) and looks at the mastermind, the
scheduler's plan and the camera's last frame while the night goes on.
"""

from __future__ import annotations

import asyncio
import os
import re
import signal
import sys
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path

import pytest
from playwright.async_api import Page, expect

from .observatory import login

PASSWORD = "watch-the-night-9"
ACTIONS = re.compile(r"^(wait|run_task|open_up|focus|close_and_park)$")
WELCOME = re.compile(r"nightcrew console at (http://127\.0\.0\.1:\d+/)")


@asynccontextmanager
async def sim_night(tmp: Path, *, hours: float, speed: float, start: str | None = None) -> AsyncIterator[str]:
    """``nightcrew sim --console 0`` as a process; yields the console's URL once it listens.

    The sim prints ``nightcrew console at URL`` once the console listens (on a free port, as 0
    asks); its other output is read on so that a full pipe never stalls the night.
    """
    env = {**os.environ, "NIGHTCREW_CONSOLE_PASSWORD": PASSWORD}
    extra = ["--start", start] if start else []
    process = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "nightcrew", "sim", "--console", "0", "--out", str(tmp / "night"),
        "--hours", str(hours), "--speed", str(speed), *extra,
        env=env, stdout=asyncio.subprocess.DEVNULL, stderr=asyncio.subprocess.PIPE,
    )  # fmt: skip
    assert process.stderr is not None
    stderr = process.stderr
    drain: asyncio.Task[bytes] | None = None
    try:
        seen: list[str] = []
        async with asyncio.timeout(180):  # the observatory starts, then the console listens
            while not (found := WELCOME.search(line := (await stderr.readline()).decode())):
                assert line, f"the sim ended before its console listened: {seen}"
                seen.append(line)
        drain = asyncio.create_task(stderr.read())
        yield found.group(1)
    finally:
        if process.returncode is None:
            process.send_signal(signal.SIGINT)  # the sim stops the night cleanly on Ctrl-C
            try:
                await asyncio.wait_for(process.wait(), 60)
            except TimeoutError:
                process.kill()
                await process.wait()
        if drain is not None:
            await drain


@pytest.fixture
async def sim_console(tmp_path: Path) -> AsyncIterator[str]:
    """A simulated night (6 clock hours from dusk at 100x: at most ~4 wall minutes) with its console."""
    async with sim_night(tmp_path, hours=6, speed=100) as url:
        yield url


async def test_sim_console_shows_the_night_live(page: Page, sim_console: str) -> None:
    await login(page, sim_console, ("operator", PASSWORD))
    await page.click("#module-list li[data-module='mastermind'] a")
    await expect(page.locator("#mm-action")).to_have_text(ACTIONS)
    await expect(page.locator("#mm-description")).not_to_be_empty()
    await expect(page.locator("#mm-conditions")).to_contain_text("Sun ")

    await page.click("#module-list li[data-module='scheduler'] a")
    await expect(page.locator("#plan-summary")).to_contain_text("objective", timeout=120_000)
    await page.click("details:has(#plan-slots) summary")
    await expect(page.locator("#plan-slots tr")).not_to_have_count(0)
    await expect(page.locator("#plan-slots")).to_contain_text("Twilight sky flats")

    await page.click("#module-list li[data-module='camera'] a")
    await expect(page.locator("#last-image")).to_have_attribute(
        "data-image-id", re.compile(r"^\d+$"), timeout=120_000
    )
    assert await page.locator("#last-image").evaluate("(img) => img.naturalWidth") > 0
