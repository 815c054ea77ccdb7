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


def test_a_computing_section_runs_the_clock_at_real_time() -> None:
    clock = AcceleratedClock("2026-11-22T18:00:00", speed=100)
    before = clock.time()
    with clock.computing():
        time.sleep(0.2)  # blocking work: 0.2 s of wall time
        inside = clock.time() - before
    assert inside == pytest.approx(0.2, abs=0.05)  # not 20 s
    assert clock.lag() == pytest.approx(0.2 * 0.99, abs=0.05)
    resumed = clock.time()
    time.sleep(0.1)
    assert clock.time() - resumed == pytest.approx(10, rel=0.3)  # full speed again


async def test_nested_and_overlapping_sections_slow_the_clock_once() -> None:
    clock = AcceleratedClock("2026-11-22T18:00:00", speed=100)
    before = clock.time()

    async def compute(wall: float) -> None:
        with clock.computing():
            await asyncio.sleep(wall)

    with clock.computing():
        await asyncio.gather(compute(0.1), compute(0.2))
    assert clock.time() - before == pytest.approx(0.2, abs=0.05)


async def test_a_sleep_lasts_its_clock_seconds_when_the_clock_is_slowed_meanwhile() -> None:
    clock = AcceleratedClock("2026-11-22T18:00:00", speed=100)

    async def slow_down() -> None:
        await asyncio.sleep(0.05)
        with clock.computing():
            await asyncio.sleep(0.3)

    before, started = clock.time(), time.monotonic()
    await asyncio.gather(clock.sleep(20), slow_down())  # 20 s: 0.2 s of wall time at full speed
    assert clock.time() - before >= 20
    assert time.monotonic() - started > 0.4  # the 0.3 s section added ~0.3 s of wall time


async def test_a_timeout_counts_clock_seconds_across_a_computing_section() -> None:
    clock = AcceleratedClock("2026-11-22T18:00:00", speed=100)
    before = clock.time()
    async with clock.timeout(10):  # 0.1 s of wall time at full speed
        with clock.computing():
            await asyncio.sleep(0.3)  # 0.3 clock seconds
        await clock.sleep(5)
    assert clock.time() - before < 10
    with pytest.raises(TimeoutError):
        async with clock.timeout(10) as deadline:
            with clock.computing():
                await asyncio.sleep(0.2)
            await clock.sleep(1000)
    assert deadline.expired()
    # Wall-clock lag on a busy machine adds clock time here (x100, by the accelerated clock's
    # design), so the bounds tell the two behaviours apart instead: never early, and the 0.5 wall
    # seconds of computing counted as clock seconds, not as the 50 they would be if accelerated.
    elapsed = clock.time() - before
    assert 0.3 + 5 + 10 - 0.01 <= elapsed < 50, elapsed  # the 0.2-s section is inside the 10 s


async def test_a_timeout_can_be_moved_and_has_a_wall_grace() -> None:
    clock = AcceleratedClock("2026-11-22T18:00:00", speed=100)
    started = time.monotonic()
    with pytest.raises(TimeoutError):
        async with clock.timeout(1000, grace=0.2) as deadline:
            deadline.reschedule(10)  # 0.1 s of wall time, then the 0.2 s of grace
            await clock.sleep(10_000)
    assert 0.25 < time.monotonic() - started < 0.6


async def test_a_shared_clock_ignores_computing_sections() -> None:
    wall_start = datetime.fromtimestamp(time.time(), tz=UTC).isoformat()
    clock = AcceleratedClock("2026-11-10T17:50:00", speed=100, wall_start=wall_start)
    before = clock.time()
    with clock.computing():  # other processes share this time: it must not fall behind theirs
        await asyncio.sleep(0.1)
    assert clock.time() - before == pytest.approx(10, rel=0.3)
    assert clock.lag() == 0
