"""Why a block is not in a plan, constraint by constraint, in words a person can act on.

For each block the solver left out, the first of these that applies is the reason:

1. a constraint that holds at no time of the (rest of the) night: its windows lie outside the
   night, the Sun is never low enough, the airmass never low enough, the Moon closer than its
   limit all night, the Moon too bright all night (each that applies is named, joined by ``;``);
2. the constraints hold somewhere, but never together;
3. the block is longer (with set-up and slew) than any stretch of time in which it is observable;
4. otherwise it could start somewhere, and the blocks planned there displaced it: they are named,
   with "higher-priority" when every one of them has a higher priority.

Pure: the problem and the plan in, a mapping of block id to reason out.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from datetime import UTC, datetime, timedelta

import numpy as np
import numpy.typing as npt

from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.scheduler.blocks import SchedulableBlock
from nightcrew.robotic.scheduler.constraints import (
    AirmassConstraint,
    Constraint,
    MoonDistanceConstraint,
    MoonIlluminationConstraint,
    SunAltitudeConstraint,
    WindowConstraint,
)
from nightcrew.robotic.scheduler.problem import SchedulingProblem
from nightcrew.robotic.scheduler.sky import SkyGrid

__all__ = ["NIGHT_OVER", "unplanned_reasons"]

BoolArray = npt.NDArray[np.bool_]

#: The reason for every block when nothing of the night is left to plan.
NIGHT_OVER = "the night is over"


def _never(constraint: Constraint, block: SchedulableBlock, night: str) -> str:
    """Why ``constraint`` never holds for ``block`` (``night``: the planned span, for windows)."""
    limits = block.constraints
    if isinstance(constraint, WindowConstraint):
        return f"its windows lie outside the night ({night})"
    if isinstance(constraint, SunAltitudeConstraint):
        return f"the Sun is never below {limits.max_sun_altitude:g}° in the night (max_sun_altitude)"
    if isinstance(constraint, AirmassConstraint):
        return f"never above the airmass limit: airmass never <= {limits.max_airmass:g} in the night"
    if isinstance(constraint, MoonDistanceConstraint):
        return f"Moon closer than {limits.min_moon_distance:g}° all night (min_lunar_distance)"
    if isinstance(constraint, MoonIlluminationConstraint):
        return f"Moon more than {limits.max_moon_illumination:g} illuminated all night (max_lunar_phase)"
    return f"{type(constraint).__name__} never holds in the night"


def unplanned_reasons(
    problem: SchedulingProblem,
    slots: Sequence[PlannedSlot],
    constraints: Sequence[Constraint],
    *,
    names: Mapping[str, str] | None = None,
    priorities: Mapping[str, float] | None = None,
) -> dict[str, str]:
    """Block id → why it is not among ``slots``, for every block of ``problem`` left out.

    Args:
        problem: What the solver saw (its visibility is every constraint together).
        slots: The plan (the slot in progress too: it displaces like any other).
        constraints: The constraints the problem was built with, to test each alone.
        names: Block id → task name, to name the displacing tasks (else their ids).
        priorities: Block id → priority of the planned blocks not in ``problem`` (in progress).
    """
    planned = {slot.task_id for slot in slots}
    rows = [row for row, block in enumerate(problem.blocks) if block.id not in planned]
    if not rows:
        return {}
    grid = problem.grid
    if grid.n_slices == 0:
        return {problem.blocks[row].id: NIGHT_OVER for row in rows}
    sky = SkyGrid(grid, problem.site, [problem.blocks[row] for row in rows])
    alone = [(constraint, constraint(sky)) for constraint in constraints]
    can_start = problem.can_start
    span = f"{_time(grid.start):%Y-%m-%d %H:%M} - {_time(grid.end):%H:%M} UTC"
    every_priority = {**(priorities or {}), **{b.id: b.priority for b in problem.blocks}}
    reasons: dict[str, str] = {}
    for index, row in enumerate(rows):
        block = problem.blocks[row]
        never = [_never(c, block, span) for c, ok in alone if not ok[index].any()]
        if never:
            reasons[block.id] = "; ".join(never)
        elif not problem.visible[row].any():
            reasons[block.id] = "its constraints never hold at the same time in the night"
        elif not can_start[row].any():
            longest = _longest_run(problem.visible[row], grid.durations) / 60.0
            needed = float(problem.occupancy_s[row]) / 60.0
            reasons[block.id] = (
                f"longer ({needed:.0f} min with set-up and slew) than any usable gap"
                f" (the longest: {longest:.0f} min)"
            )
        else:
            blockers = _displacing(problem, row, slots)
            reasons[block.id] = _displaced(block, blockers, every_priority.get, names or {})
    return reasons


def _displacing(problem: SchedulingProblem, row: int, slots: Sequence[PlannedSlot]) -> list[str]:
    """Ids of the planned blocks that overlap any start the block could have had, by start."""
    starts = problem.grid.edges[np.flatnonzero(problem.can_start[row])]
    ends = starts + float(problem.occupancy_s[row])
    found = []
    for slot in slots:
        begin, end = slot.start.timestamp(), slot.end.timestamp()
        if np.any((starts < end) & (ends > begin)):
            found.append(slot.task_id)
    return found


def _displaced(
    block: SchedulableBlock,
    blockers: list[str],
    priority_of: Callable[[str], float | None],
    names: Mapping[str, str],
) -> str:
    if not blockers:
        return "left out by the solver (no better plan found within its work limit)"
    named = ", ".join(names.get(blocker, blocker) for blocker in blockers)
    higher = all((priority_of(b) or 0.0) > block.priority for b in blockers)
    if higher:
        return f"displaced by higher-priority tasks {named}"
    return f"displaced by tasks {named} (the plan is worth more with them)"


def _longest_run(row: BoolArray, durations: npt.NDArray[np.float64]) -> float:
    """Seconds of the longest run of True slices."""
    padded = np.concatenate(([0], row.astype(np.int8), [0]))
    edges = np.flatnonzero(np.diff(padded))
    seconds = np.concatenate(([0.0], np.cumsum(durations)))
    return float((seconds[edges[1::2]] - seconds[edges[::2]]).max(initial=0.0))


def _time(unix_time: float) -> datetime:
    return datetime(1970, 1, 1, tzinfo=UTC) + timedelta(seconds=unix_time)
