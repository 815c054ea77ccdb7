"""Fixtures all test directories share: in-process observatories (nightcrew.testing) on virtual time."""

from __future__ import annotations

from collections.abc import AsyncIterator, Iterator

import pytest

from nightcrew.testing import Observatory
from nightcrew.testing.solver import running_solver
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


@pytest.fixture(scope="session")
def solver_url() -> Iterator[str]:
    """The plate-solving service (``nightcrew solver``), one for the session: it starts in ~1 s."""
    with running_solver() as url:
        yield url
