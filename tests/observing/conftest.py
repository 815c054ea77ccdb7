"""Focus series, acquisition, guiding and seeing on simulated observatories on virtual time."""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from contextlib import AbstractAsyncContextManager, asynccontextmanager

import pytest

from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile

__all__ = ["ObservatoryFactory", "observatory_at"]

ObservatoryFactory = Callable[[], AbstractAsyncContextManager[Observatory]]


@pytest.fixture
def observatory_at() -> ObservatoryFactory:
    """``async with observatory_at() as obs``: an observatory on a virtual clock (shared in-memory
    files cleared after)."""

    @asynccontextmanager
    async def make() -> AsyncIterator[Observatory]:
        obs = Observatory()
        try:
            yield obs
        finally:
            await obs.close()
            MemoryFile.clear_shared()

    return make
