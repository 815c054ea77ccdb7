"""Benchmark of the mastermind's early-start check while it waits for the next task.

Run: ``.venv/bin/python bench/early_start.py [runs]``.

The mastermind looks at the world every ``poll_interval`` (30 clock s in the simulated night) and,
while nothing is due, asks whether the next task may start early. Here it waits 30 min for a slot
whose target rises at 22:17 (60 steps; the task is ``early_start.yaml`` beside this file, the
scenario of tests/robotic/test_mastermind_early_start.py); the table gives the event-loop
milliseconds of the whole wait (median and min of ``runs``), asking each step afresh
(``startable_now``) and through ``EarlyStarts``, which keeps the answer per (task, slot).
"""

from __future__ import annotations

import statistics
import sys
import time
from collections.abc import Callable
from datetime import UTC, datetime, timedelta
from pathlib import Path

from nightcrew.robotic.mastermind import EarlyStarts, Slot, SunLimits, startable_now
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.tasks import TaskState, TaskStatus, load_request_group_file, tasks_of_group
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0)
NOW = datetime(2024, 1, 15, 22, tzinfo=UTC)
POLL, WAIT = timedelta(seconds=30), timedelta(minutes=30)
STEPS = [NOW + POLL * i for i in range(int(WAIT / POLL))]

# Its target rises above airmass 2 at 22:17.
(TASK,) = tasks_of_group(
    load_request_group_file(Path(__file__).with_name("early_start.yaml")),
    "g1",
    ["7"],
    [TaskStatus(state=TaskState.SCHEDULED)],
)
SLOT = Slot(
    planned=PlannedSlot("7", NOW + WAIT, NOW + 2 * WAIT), name="rising", needs_sky=True, sun=SunLimits(-12.0)
)


def each_step_afresh() -> int:
    return sum(startable_now(TASK, SITE, now, SLOT.start) for now in STEPS)


def early_starts() -> int:
    early = EarlyStarts(SITE, WAIT)
    return sum(early.mark([SLOT], {"7": TASK}, now)[0].startable_now for now in STEPS)


def _timed(case: Callable[[], int], runs: int) -> tuple[list[float], int]:
    times, startable = [], 0
    for _ in range(runs):
        start = time.perf_counter()
        startable = case()
        times.append((time.perf_counter() - start) * 1e3)
    return times, startable


def main(runs: int) -> None:
    print(f"waiting {WAIT.total_seconds() / 60:g} min, {len(STEPS)} steps; {runs} runs")
    print(f"{'case':<28} {'median ms':>10} {'min ms':>8} {'steps startable':>16}")
    for name, case in (("startable_now each step", each_step_afresh), ("EarlyStarts (kept)", early_starts)):
        times, startable = _timed(case, runs)
        print(f"{name:<28} {statistics.median(times):>10.1f} {min(times):>8.1f} {startable:>16}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 7)
