"""The modules' test observatory (one network, one fast clock, fixed epoch and site)."""

from __future__ import annotations

from collections.abc import AsyncIterator

import pytest

from nightcrew.testing import Observatory


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    """Clock at 2000x: a 10-minute temperature plateau passes in 0.3 s."""
    obs = Observatory(speed=2000.0)
    try:
        yield obs
    finally:
        await obs.close()
