"""wait_for: polls a condition on a clock, returns the time it took, fails past its bound."""

from __future__ import annotations

import pytest

from nightcrew.clock import AcceleratedClock
from nightcrew.testing import EPOCH, wait_for


async def test_returns_the_clock_seconds_until_the_condition_held() -> None:
    clock = AcceleratedClock(EPOCH, speed=100.0)
    due = clock.time() + 30.0
    took = await wait_for(lambda: clock.time() >= due, 60.0, clock=clock, interval=1.0)
    assert 30.0 <= took < 60.0


async def test_a_condition_that_holds_at_once_takes_no_time() -> None:
    clock = AcceleratedClock(EPOCH, speed=100.0)
    assert await wait_for(lambda: True, 0.0, clock=clock) == pytest.approx(0.0, abs=1.0)


async def test_an_async_condition_is_awaited() -> None:
    clock = AcceleratedClock(EPOCH, speed=100.0)
    calls: list[float] = []

    async def third_call() -> bool:
        calls.append(clock.time())
        return len(calls) >= 3

    await wait_for(third_call, 60.0, clock=clock, interval=2.0)
    assert len(calls) == 3 and calls[2] - calls[0] >= 4.0


async def test_fails_naming_what_was_awaited_after_the_bound() -> None:
    clock = AcceleratedClock(EPOCH, speed=100.0)
    start = clock.time()
    with pytest.raises(AssertionError, match="the roof opening: not within 20 clock seconds"):
        await wait_for(lambda: False, 20.0, clock=clock, message="the roof opening")
    assert 20.0 <= clock.time() - start < 60.0


async def test_the_wall_clock_by_default() -> None:
    with pytest.raises(AssertionError, match=r"not within 0\.2 clock seconds"):
        await wait_for(lambda: False, 0.2)


async def test_bad_bounds_are_refused() -> None:
    with pytest.raises(ValueError, match="clock_seconds must be >= 0, got -1"):
        await wait_for(lambda: True, -1.0)
    with pytest.raises(ValueError, match="interval must be > 0 clock seconds, got 0"):
        await wait_for(lambda: True, 1.0, interval=0.0)
