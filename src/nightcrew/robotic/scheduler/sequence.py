"""The solver's plan with every transition honoured exactly (the slew model), and gaps refilled.

The solver places blocks with a per-block transition allowance that is a *lower bound* (the
quickest way into the block from any other block: :func:`least_transitions`), so its upper bound
holds for every schedule that pays the real, sequence-dependent transitions. This module then walks
the plan in time order paying each real transition (from the block before, at the time it ends):
a block that no longer fits its visibility or window is dropped, and blocks left out are tried in
the gaps where they delay nothing after them. The result keeps every constraint and every
transition exactly; its value over the solver's bound is the proven quality.

Least transitions are optimistic, so the first plan loses blocks to the real ones; the scheduler
also solves with typical allowances (the :data:`TYPICAL_QUANTILES` of the transitions into each
block, no bound) and keeps whichever sequenced plan is worth more.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nightcrew.robotic.scheduler.blocks import SchedulableBlock
from nightcrew.robotic.scheduler.problem import SchedulingProblem
from nightcrew.robotic.scheduler.slew import Pointing, SlewModel
from nightcrew.site import Site

__all__ = ["TYPICAL_QUANTILES", "SequencedSlot", "least_transitions", "pointing_of", "sequence"]

#: The solver's further plans allow each block these quantiles of the transitions into it.
TYPICAL_QUANTILES = (0.5, 0.9)

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


def pointing_of(block: SchedulableBlock) -> Pointing:
    """Where the block points, with its filters and instrument."""
    return Pointing(
        block.target.ra, block.target.dec, block.first_filter, block.last_filter, block.instrument
    )


def least_transitions(
    model: SlewModel,
    site: Site,
    blocks: Sequence[SchedulableBlock],
    times: Sequence[float],
    *,
    quantile: float = 0.0,
) -> FloatArray:
    """Per block, the least transition into it from any other block at any of ``times`` (one for an
    equatorial mount without a dome: its slews do not depend on the time); with ``quantile`` > 0
    that quantile over the other blocks instead of the least (a typical transition, no bound)."""
    n = len(blocks)
    if n < 2:
        return np.zeros(n)
    ra = np.array([b.target.ra for b in blocks])
    dec = np.array([b.target.dec for b in blocks])
    slews = np.min(
        [model.slew_s(site, (ra[:, None], dec[:, None]), (ra[None, :], dec[None, :]), t) for t in times],
        axis=0,
    )
    last = np.array([b.last_filter for b in blocks])[:, None]
    first = np.array([b.first_filter for b in blocks])[None, :]
    instrument = np.array([b.instrument for b in blocks])
    changes = np.where((first != "") & (last != "") & (first != last), model.filter_change_s, 0.0)
    changes = changes + np.where(
        (instrument[:, None] != "")
        & (instrument[None, :] != "")
        & (instrument[:, None] != instrument[None, :]),
        model.instrument_setup_s,
        0.0,
    )
    total = slews + changes
    np.fill_diagonal(total, np.nan)
    return np.asarray(np.nanquantile(total, quantile, axis=0), dtype=np.float64)


@dataclass(frozen=True)
class SequencedSlot:
    """Block ``row`` holds the telescope from ``start`` (its transition begins) to ``end`` (its
    observation ends), Unix seconds."""

    row: int
    start: float
    end: float


class _Checker:
    """Whether a block may occupy ``[start, end]``: every slice of the grid it touches is visible."""

    def __init__(self, problem: SchedulingProblem) -> None:
        self.edges = problem.grid.edges
        self.count = np.zeros((len(problem.blocks), problem.grid.n_slices + 1), dtype=np.int64)
        np.cumsum(problem.visible, axis=1, out=self.count[:, 1:])

    def fits(self, row: int, start: float, end: float) -> bool:
        if start < self.edges[0] - 1e-3 or end > self.edges[-1] + 1e-3:
            return False
        first = max(0, int(np.searchsorted(self.edges, start + 1e-3, side="right")) - 1)
        last = int(np.searchsorted(self.edges, end - 1e-3, side="left"))
        return bool(self.count[row, last] - self.count[row, first] == last - first)


def sequence(
    problem: SchedulingProblem,
    starts: IntArray,
    model: SlewModel,
    *,
    begin_at: Pointing | None = None,
) -> list[SequencedSlot]:
    """The plan ``starts`` (start edge per block, -1: not placed) with exact transitions.

    Args:
        problem: What the solver saw (its ``overhead_s`` holds the setup and the least transition).
        starts: The solver's start edge per block.
        model: The slew model.
        begin_at: Where the telescope points when the plan begins (None: the first block's slew is
            not counted, as the solver did not).
    """
    site, blocks = problem.site, problem.blocks
    pointings = [pointing_of(b) for b in blocks]
    # Seconds each block needs besides its transition: set-up, flip allowance, observation.
    fixed = np.array([b.setup_s + b.duration_s for b in blocks]) + problem.flip_s
    checker = _Checker(problem)

    def transition(before: int | None, after: int, at: float) -> float:
        origin = begin_at if before is None else pointings[before]
        return 0.0 if origin is None else model.transition_s(site, origin, pointings[after], at)

    slots: list[SequencedSlot] = []
    for row in sorted(np.flatnonzero(starts >= 0), key=lambda r: (problem.grid.edges[starts[r]], r)):
        previous = slots[-1] if slots else None
        start = max(float(problem.grid.edges[starts[row]]), previous.end if previous else problem.grid.start)
        end = start + transition(previous.row if previous else None, int(row), start) + fixed[row]
        if checker.fits(int(row), start, end):
            slots.append(SequencedSlot(int(row), start, end))
    return _fill(problem, slots, fixed, transition, checker)


def _insert(
    row: int,
    gap_start: float,
    later_starts: FloatArray,
    before: SequencedSlot | None,
    after: SequencedSlot | None,
    fixed: FloatArray,
    transition: Callable[[int | None, int, float], float],
    checker: _Checker,
) -> list[SequencedSlot] | None:
    """Block ``row`` in the gap after ``before`` (at its end or at one of ``later_starts``), and
    ``after`` with its new transition, if ``after`` still ends by its old end; else None."""
    origin = before.row if before else None
    for edge in (gap_start, *later_starts):
        # Slew early so that the block itself begins at the edge (where the solver found it fits).
        start = max(gap_start, float(edge) - transition(origin, row, float(edge)))
        end = start + transition(origin, row, start) + fixed[row]
        if not checker.fits(row, start, end):
            start = float(edge)
            end = start + transition(origin, row, start) + fixed[row]
            if not checker.fits(row, start, end):
                continue
        if after is None:
            return [SequencedSlot(row, start, end)]
        next_start = max(end, after.start)
        next_end = next_start + transition(row, after.row, next_start) + fixed[after.row]
        if next_end <= after.end + 1e-6:  # nothing after it moves
            return [SequencedSlot(row, start, end), SequencedSlot(after.row, next_start, next_end)]
    return None


def _fill(
    problem: SchedulingProblem,
    slots: list[SequencedSlot],
    fixed: FloatArray,
    transition: Callable[[int | None, int, float], float],
    checker: _Checker,
) -> list[SequencedSlot]:
    """``slots`` with left-out blocks put into gaps where the next block still ends in time."""
    placed = {s.row for s in slots}
    edges = problem.grid.edges
    density = problem.weights / np.maximum(fixed, 1.0)
    for row in (int(r) for r in np.argsort(-density, kind="stable")):
        if row in placed or not problem.can_start[row].any():
            continue
        own_starts = edges[np.flatnonzero(problem.can_start[row])]
        for index in range(len(slots) + 1):
            before = slots[index - 1] if index > 0 else None
            after = slots[index] if index < len(slots) else None
            gap_start = before.end if before else problem.grid.start
            gap_end = after.start if after else problem.grid.end
            room = (after.end - fixed[after.row] if after else problem.grid.end) - gap_start
            if fixed[row] > room:  # the cheap refusal first: most gaps are too short
                continue
            later = own_starts[(own_starts > gap_start) & (own_starts < gap_end)]
            inserted = _insert(row, gap_start, later, before, after, fixed, transition, checker)
            if inserted is not None:
                slots[index : index + 1 if after else index] = inserted
                placed.add(row)
                break
    return slots
