"""A faster observatory for automation tests (the utils and image tests import it from here)."""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable

import pytest

from nightcrew.vfs import MemoryFile
from tests.modules.conftest import Observatory

__all__ = ["fast_observatory", "wait_for"]


@pytest.fixture
async def fast_observatory() -> AsyncIterator[Observatory]:
    """Clock at 400x: a simulated quarter of an hour passes in about 2 s."""
    obs = Observatory(speed=200.0)  # modest: event-loop latency under load counts x speed
    try:
        yield obs
    finally:
        await obs.close()
        MemoryFile.clear_shared()


async def wait_for(observatory: Observatory, condition: Callable[[], bool], clock_seconds: float) -> float:
    """Clock seconds until ``condition()`` holds (checked each clock second); fails past ``clock_seconds``."""
    start = observatory.clock.time()
    while not condition():
        assert observatory.clock.time() - start < clock_seconds, "condition not met in time"
        await observatory.clock.sleep(1.0)
    return observatory.clock.time() - start
