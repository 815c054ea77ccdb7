"""Clocks: the accelerated clock moves and waits ``speed`` times faster than the wall."""

from __future__ import annotations

import time
from datetime import UTC, datetime

import pytest

from nightcrew.clock import AcceleratedClock, RealClock


def test_real_clock_follows_the_wall() -> None:
    clock = RealClock()
    assert abs(clock.time() - time.time()) < 0.01
    assert clock.now().tzinfo is UTC
    assert clock.to_wall(5) == 5


async def test_accelerated_clock_starts_at_its_epoch_and_runs_fast() -> None:
    clock = AcceleratedClock("2026-11-22T18:00:00", speed=100)
    assert abs((clock.now() - datetime(2026, 11, 22, 18, tzinfo=UTC)).total_seconds()) < 1
    start_clock, start_wall = clock.time(), time.monotonic()
    await clock.sleep(20)  # 0.2 s of wall time
    wall = time.monotonic() - start_wall
    assert 0.19 <= wall < 0.5
    assert clock.time() - start_clock == pytest.approx(wall * 100, rel=0.01)


async def test_accelerated_clock_timeout_is_in_clock_seconds() -> None:
    clock = AcceleratedClock(datetime(2026, 1, 1, tzinfo=UTC), speed=50)
    started = time.monotonic()
    with pytest.raises(TimeoutError):
        async with clock.timeout(10):  # 0.2 s of wall time
            await clock.sleep(1000)
    assert time.monotonic() - started < 1.0


def test_accelerated_clock_refuses_a_bad_speed() -> None:
    with pytest.raises(ValueError, match="speed must be > 0"):
        AcceleratedClock("2026-11-22T18:00:00", speed=0)
