"""Focus series, acquisition, guiding and seeing on simulated observatories at chosen clock speeds."""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from contextlib import AbstractAsyncContextManager, asynccontextmanager

import pytest

from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile

__all__ = ["ObservatoryFactory", "observatory_at"]

ObservatoryFactory = Callable[[float], AbstractAsyncContextManager[Observatory]]


@pytest.fixture
def observatory_at() -> ObservatoryFactory:
    """``async with observatory_at(speed) as obs``: an observatory whose clock runs ``speed`` times fast."""

    @asynccontextmanager
    async def make(speed: float) -> AsyncIterator[Observatory]:
        obs = Observatory(speed=speed)
        try:
            yield obs
        finally:
            await obs.close()
            MemoryFile.clear_shared()

    return make
