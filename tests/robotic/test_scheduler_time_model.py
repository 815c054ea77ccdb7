"""The time model: windows at odd minutes lose nothing to the grid, and the plan is deterministic."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

import numpy as np

from nightcrew.robotic.scheduler import Night, SchedulableBlock, Scheduler, Target
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
START = datetime(2024, 1, 15, 17, 0, tzinfo=UTC)  # the Sun is below -12° from 17:00 to 06:00 UTC
NIGHT = Night(START, START + timedelta(hours=13), SITE)
CIRCUMPOLAR = Target(ra=60.0, dec=80.0)


def _odd_minute_windows(count: int) -> list[SchedulableBlock]:
    """Back-to-back 15-min windows opening at odd minutes (17:07, 17:22, ...), each for a block of
    11-15 min with its set-up and the scheduler's slew allowance: none fits a 5-min grid."""
    rng = np.random.default_rng(7)
    blocks = []
    for index in range(count):
        opens = START + timedelta(minutes=7 + 15 * index)
        occupancy = float(rng.uniform(11 * 60, 15 * 60))
        blocks.append(
            SchedulableBlock(
                id=f"tc{index:02d}",
                priority=float(rng.uniform(1, 10)),
                duration_s=occupancy - 60.0 - 30.0,  # set-up 60 s, slew allowance 30 s
                target=CIRCUMPOLAR,
                windows=((opens, opens + timedelta(minutes=15)),),
                setup_s=60.0,
            )
        )
    return blocks


def test_requests_with_15_minute_windows_at_odd_minutes_are_all_placed() -> None:
    blocks = _odd_minute_windows(40)
    schedule = Scheduler(step_s=300.0, slew_overhead_s=30.0).schedule(blocks, NIGHT)
    assert sorted(s.task_id for s in schedule.slots) == [b.id for b in blocks]
    for slot, block in zip(schedule.slots, blocks, strict=True):
        ((opens, closes),) = block.windows
        assert opens <= slot.start and slot.end <= closes
    for earlier, later in zip(schedule.slots, schedule.slots[1:], strict=False):
        assert earlier.end <= later.start
    # The plain 5-min grid (astroplan's view) can place none of them.
    assert Scheduler(solver="priority", slew_overhead_s=30.0).schedule(blocks, NIGHT).slots == ()


def test_the_same_blocks_give_the_same_plan_whatever_the_time_limit() -> None:
    blocks = synthetic_blocks(NIGHT, 60, seed=3)
    first = Scheduler(time_limit_s=0.001).schedule(blocks, NIGHT)
    second = Scheduler(time_limit_s=1000.0).schedule(blocks, NIGHT)
    assert first.slots == second.slots
    assert first.objective == second.objective and first.bound == second.bound
    assert first.bound is not None and first.objective <= first.bound
