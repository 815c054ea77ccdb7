"""Fixtures all test directories share: in-process observatories (nightcrew.testing) on a fast clock."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    """Clock at 100x: a 60 s roof closing takes 0.6 s of wall time."""
    async with Observatory(speed=100.0) as obs:
        yield obs


@pytest.fixture
async def fast_observatory() -> AsyncIterator[Observatory]:
    """Clock at 200x for the automation tests: a simulated quarter of an hour passes in about 5 s."""
    obs = Observatory(speed=200.0)  # modest: event-loop latency under load counts x speed
    try:
        yield obs
    finally:
        await obs.close()
        MemoryFile.clear_shared()
