"""The modules' test observatory (one network, one virtual clock, fixed epoch and site)."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from nightcrew.testing import Observatory


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    """On a virtual clock: a 10-minute temperature plateau passes in no wall time."""
    obs = Observatory()
    try:
        yield obs
    finally:
        await obs.close()
