"""A Comet broker per test, in a network namespace of its own (a few hundred ms to start)."""

from __future__ import annotations

import os
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.testing.comet import CometBroker
from nightcrew.testing.hosts import hosts_missing


@pytest.fixture
def comet(tmp_path: Path) -> Iterator[CometBroker]:
    missing = hosts_missing() + (
        [] if Path(sys.executable).with_name("twistd").exists() else ["comet (twistd)"]
    )
    if missing:
        if os.environ.get("CI") == "true":
            pytest.fail(f"missing for the broker's network namespace: {', '.join(missing)}")
        pytest.skip(f"missing for the broker's network namespace: {', '.join(missing)}")
    broker = CometBroker(tmp_path)
    broker.start()
    try:
        yield broker
    finally:
        broker.stop()
