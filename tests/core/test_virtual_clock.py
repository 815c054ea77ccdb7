"""The virtual clock: time moves only when every task waits on it, and work costs what it declares."""

from __future__ import annotations

import asyncio
import time

import pytest

from nightcrew.clock import WORK_COSTS, VirtualClock

START = "2026-11-10T18:00:00+00:00"


async def test_the_clock_jumps_to_each_wake_up_in_turn() -> None:
    clock = VirtualClock(START)
    t0 = clock.time()
    woken: list[tuple[str, float]] = []

    async def sleeper(name: str, seconds: float) -> None:
        await clock.sleep(seconds)
        woken.append((name, clock.time() - t0))

    await asyncio.gather(sleeper("hour", 3600.0), sleeper("minute", 60.0), asyncio.sleep(10.0))
    assert woken == [("minute", 60.0), ("hour", 3600.0)]
    assert clock.now().isoformat() == "2026-11-10T19:00:00+00:00"


async def test_the_clock_stands_still_while_a_thread_job_runs() -> None:
    clock = VirtualClock(START)
    t0 = clock.time()
    sleeping = asyncio.ensure_future(clock.sleep(1.0))
    await asyncio.to_thread(time.sleep, 0.2)  # 0.2 wall seconds: no clock time at all
    assert clock.time() == t0
    assert not sleeping.done()
    await sleeping
    assert clock.time() - t0 == 1.0


async def test_thread_results_arrive_in_the_order_they_were_asked_for() -> None:
    VirtualClock(START).attach()
    order: list[str] = []

    async def job(name: str, wall_seconds: float) -> None:
        await asyncio.to_thread(time.sleep, wall_seconds)
        order.append(name)

    # The slow job was asked for first: its result comes first, however the threads finish.
    await asyncio.gather(job("slow", 0.3), job("fast", 0.0), job("faster", 0.0))
    assert order == ["slow", "fast", "faster"]


async def test_work_costs_its_declared_clock_time_not_the_machines() -> None:
    clock = VirtualClock(START, work={"plate_solve": 12.0})
    t0 = clock.time()
    async with clock.work("plate_solve"):
        await asyncio.to_thread(time.sleep, 0.2)
        assert clock.time() == t0  # inside, the clock stands still
    assert clock.time() - t0 == 12.0
    async with clock.work("write_frame"):
        pass
    assert clock.time() - t0 == 12.0 + WORK_COSTS["write_frame"]


async def test_others_carry_on_while_a_task_waits_out_its_work() -> None:
    clock = VirtualClock(START)
    t0 = clock.time()
    ticks: list[float] = []

    async def ticker() -> None:
        for _ in range(3):
            await clock.sleep(1.0)
            ticks.append(clock.time() - t0)

    async def solver() -> float:
        async with clock.work("plate_solve"):  # 5 clock seconds
            pass
        return clock.time() - t0

    _, solved = await asyncio.gather(ticker(), solver())
    assert ticks == [1.0, 2.0, 3.0] and solved == WORK_COSTS["plate_solve"]


async def test_a_clock_timeout_fires_at_its_clock_second() -> None:
    clock = VirtualClock(START)
    t0 = clock.time()
    async with clock.timeout(30.0):
        await clock.sleep(10.0)
    with pytest.raises(TimeoutError):
        async with clock.timeout(30.0):
            await clock.sleep(100.0)
    assert clock.time() - t0 == 40.0


def test_before_its_loop_runs_the_clock_shows_its_start() -> None:
    assert VirtualClock(START).now().isoformat() == START


def test_unknown_kinds_of_work_and_bad_costs_are_refused() -> None:
    with pytest.raises(ValueError, match="unknown kind of work 'platesolve'; known: write_frame"):
        VirtualClock(START, work={"platesolve": 3.0})
    with pytest.raises(ValueError, match=r"work.schedule: need a number of clock seconds >= 0, got -1"):
        VirtualClock(START, work={"schedule": -1})


async def test_a_second_clock_on_the_same_loop_shares_its_time() -> None:
    first, second = VirtualClock(START), VirtualClock("2026-11-11T00:00:00+00:00")
    first.attach()
    await first.sleep(60.0)
    t0 = second.time()
    await first.sleep(60.0)
    assert second.time() - t0 == 60.0
