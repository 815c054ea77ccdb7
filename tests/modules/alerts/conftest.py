"""A Comet broker per test (a few hundred ms to start)."""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.testing.comet import CometBroker


@pytest.fixture
def comet(tmp_path: Path) -> Iterator[CometBroker]:
    if not Path(sys.executable).with_name("twistd").exists():
        if os.environ.get("CI") == "true":
            pytest.fail("comet (twistd) is not installed")
        pytest.skip("comet (twistd) is not installed")
    broker = CometBroker(tmp_path)
    broker.start()
    try:
        yield broker
    finally:
        broker.stop()
