"""Focus series, acquisition, guiding and seeing on the simulated observatory of tests/modules."""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable
from contextlib import AbstractAsyncContextManager, asynccontextmanager

import pytest

from nightcrew.vfs import MemoryFile
from tests.modules.conftest import Observatory, observatory

__all__ = ["ObservatoryFactory", "observatory", "observatory_at"]

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
