"""Clocks: the accelerated clock moves and waits ``speed`` times faster than the wall."""

from __future__ import annotations

import asyncio
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


async def test_clocks_sharing_a_wall_start_agree_however_late_they_were_made() -> None:
    wall_start = datetime.fromtimestamp(time.time() - 5, tz=UTC).isoformat()
    first = AcceleratedClock("2026-11-10T17:50:00", speed=60, wall_start=wall_start)
    await asyncio.sleep(0.2)  # a second process starting later
    second = AcceleratedClock("2026-11-10T17:50:00", speed=60, wall_start=wall_start)
    assert abs(first.time() - second.time()) < 0.1
    # 5 s of wall time since wall_start = 300 clock seconds after the start epoch
    expected = datetime(2026, 11, 10, 17, 55, tzinfo=UTC).timestamp()
    assert second.time() == pytest.approx(expected, abs=60 * 0.5)
