"""Fixtures all test directories share: in-process observatories (nightcrew.testing) on virtual time."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    """On a virtual clock: a 60 s roof closing takes no wall time to speak of."""
    async with Observatory() as obs:
        yield obs


@pytest.fixture
async def fast_observatory() -> AsyncIterator[Observatory]:
    """On a virtual clock, for the automation tests (with the shared in-memory files cleared after)."""
    obs = Observatory()
    try:
        yield obs
    finally:
        await obs.close()
        MemoryFile.clear_shared()
