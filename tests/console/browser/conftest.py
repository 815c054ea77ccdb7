"""Fixtures of the console's browser tests: a headless Chromium, pages that record script errors,
and a simulated observatory with a console."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest
from playwright.async_api import expect

from nightcrew.testing.browser import browser, page  # noqa: F401 - the shared browser fixtures

from .observatory import Observatory

# Conditions in the page are awaited, never slept for; this bounds each wait on a busy machine.
expect.set_options(timeout=20_000)


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
