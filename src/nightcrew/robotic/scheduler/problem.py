"""One scheduling problem on arrays, shared by every solver, and a solver's answer.

:func:`build_problem` turns blocks and a night into the grid form both solvers read: which slices
each block may occupy (:func:`~nightcrew.robotic.scheduler.constraints.visibility`), how many slices
it occupies, and what placing it is worth. Solvers then only choose start slices, so the MIP and
the priority baseline are compared on exactly the same visibility, lengths and weights.

Overheads are modelled by padding: a block occupies ``setup_s + slew_overhead_s + duration_s``,
rounded up to whole slices, where ``slew_overhead_s`` is one worst-case slew (plus settling) for
every block. That over-estimates short slews between neighbours, but keeps every schedule
executable without transition variables (which would make the MIP quadratic in blocks).

A German-equatorial mount flips when its target crosses the meridian; with ``meridian_flip_s`` a
block whose target crosses the meridian while it is visible is padded by that much too. The
allowance goes with the block, not with its start (which would make lengths depend on the start
slice): a block that could cross is padded wherever it is placed, keeping the plan executable.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nightcrew.astro import local_sidereal_time
from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.scheduler.blocks import SchedulableBlock
from nightcrew.robotic.scheduler.constraints import DEFAULT_CONSTRAINTS, Constraint, startable, visibility
from nightcrew.robotic.scheduler.sky import SkyGrid, TimeGrid
from nightcrew.site import Site

__all__ = [
    "Placement",
    "SchedulingProblem",
    "build_problem",
    "check_placement",
    "density_bound",
    "meridian_crossings",
    "spans_of",
    "window_edges",
]

IntArray = npt.NDArray[np.int64]
FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]


@dataclass(frozen=True)
class SchedulingProblem:
    """Blocks on a slice grid.

    Attributes:
        grid: The slices to fill.
        site: The observatory.
        blocks: The candidate blocks; row ``b`` of every array belongs to ``blocks[b]``.
        visible: (n_blocks, n_slices): slices where all of a block's constraints hold.
        lengths: Coarse slices (of ``grid.step``) each block occupies (overheads and duration,
            rounded up): what a solver on a plain grid reads.
        spans: (n_blocks, n_slices): slices block ``b`` occupies when it starts at edge ``i``, up to
            the first edge at or after its end (0 where it would outlast the night).
        can_start: (n_blocks, n_slices): starts whose whole span is visible, at a coarse edge or at
            one of the block's own edges (its windows' openings and latest starts).
        weights: Value of placing each block: priority x observed hours.
        overhead_s: Seconds of overhead in front of each block's observation.
        flip_s: Seconds of meridian-flip allowance inside each block (0 where none may be needed).
    """

    grid: TimeGrid
    site: Site
    blocks: tuple[SchedulableBlock, ...]
    visible: BoolArray
    lengths: IntArray
    spans: IntArray
    can_start: BoolArray
    weights: FloatArray
    overhead_s: FloatArray
    flip_s: FloatArray

    def start_values(self) -> FloatArray:
        """(n_blocks, n_slices): what starting block ``b`` at edge ``i`` is worth: its weight, and
        for a time-critical block up to ``early_start_weight`` of it more, falling linearly from
        the plan's first edge to nothing at its end (so it starts as early as it can)."""
        early = np.array([b.early_start_weight for b in self.blocks], dtype=np.float64)
        starts = self.grid.edges[:-1]
        left = (self.grid.end - starts) / max(self.grid.end - starts[0], 1.0) if len(starts) else starts
        return np.asarray(self.weights[:, None] * (1.0 + early[:, None] * left[None, :]), dtype=np.float64)

    @property
    def occupancy_s(self) -> FloatArray:
        """Seconds each block holds the telescope: overheads, flip allowance and observation."""
        durations = np.array([b.duration_s for b in self.blocks], dtype=np.float64)
        return np.asarray(self.overhead_s + self.flip_s + durations, dtype=np.float64)


@dataclass(frozen=True)
class Placement:
    """A solver's choice: start slice per block (-1: not placed) and what it is worth."""

    starts: IntArray
    objective: float
    bound: float | None
    status: str


def build_problem(
    blocks: Sequence[SchedulableBlock],
    site: Site,
    start: float,
    end: float,
    *,
    step_s: float,
    slew_overhead_s: float | FloatArray,
    meridian_flip_s: float = 0.0,
    constraints: Sequence[Constraint] = DEFAULT_CONSTRAINTS,
    refine: bool = False,
) -> SchedulingProblem:
    """The grid form of ``blocks`` between Unix times ``start`` and ``end``.

    ``slew_overhead_s`` is one allowance for every block or one per block (a slew model's least
    transition into it).

    With ``refine`` the grid gets edges at every window's opening and end and, per block, at its
    end when started at a window's opening and at its latest start in a window (see
    :func:`window_edges`): a block may start at those edges of its own as well as at coarse ones.
    """
    slews = np.broadcast_to(np.asarray(slew_overhead_s, dtype=np.float64), (len(blocks),))
    if not np.all(slews >= 0):
        raise InvalidArgumentError(f"slew_overhead_s must be >= 0, got {slew_overhead_s}")
    if not meridian_flip_s >= 0:
        raise InvalidArgumentError(f"meridian_flip_s must be >= 0, got {meridian_flip_s}")
    seen: set[str] = set()
    for block in blocks:
        if not isinstance(block, SchedulableBlock):
            raise InvalidArgumentError(f"expected a SchedulableBlock, got {type(block).__name__}")
        if block.id in seen:
            raise InvalidArgumentError(f"block id {block.id!r} appears twice")
        seen.add(block.id)
    overhead = np.array([b.setup_s for b in blocks], dtype=np.float64) + slews
    # Flips are judged on the coarse grid (a refined one would only move them by minutes).
    coarse = TimeGrid.covering(start, end, step_s)
    coarse_visible = visibility(SkyGrid(coarse, site, blocks), constraints)
    flips = meridian_crossings(coarse, site, blocks, coarse_visible) * meridian_flip_s
    occupancy = overhead + flips + np.array([b.duration_s for b in blocks], dtype=np.float64)
    own = window_edges(blocks, occupancy) if refine else [np.zeros(0)] * len(blocks)
    grid = TimeGrid.refined(start, end, step_s, np.concatenate([np.zeros(0), *own])) if refine else coarse
    visible = visibility(SkyGrid(grid, site, blocks), constraints) if refine else coarse_visible
    spans = spans_of(grid, occupancy)
    allowed = np.zeros((len(blocks), grid.n_slices), dtype=np.bool_)
    allowed[:, grid.index_of(coarse.edges[:-1])[grid.index_of(coarse.edges[:-1]) >= 0]] = True
    for row, times in enumerate(own):
        index = grid.index_of(times)
        allowed[row, index[(index >= 0) & (index < grid.n_slices)]] = True
    lengths = np.array([coarse.slices_for(o) for o in occupancy], dtype=np.int64)
    weights = np.array([b.priority * b.duration_s / 3600.0 for b in blocks], dtype=np.float64)
    return SchedulingProblem(
        grid=grid,
        site=site,
        blocks=tuple(blocks),
        visible=visible,
        lengths=lengths,
        spans=spans,
        can_start=startable(visible, spans) & allowed,
        weights=weights,
        overhead_s=overhead,
        flip_s=flips,
    )


def window_edges(blocks: Sequence[SchedulableBlock], occupancy: FloatArray) -> list[FloatArray]:
    """Per block, the times a refined grid adds for it: each window's opening, its end, the block's
    end when started at the opening and its latest start (end - occupancy)."""
    result = []
    for block, seconds in zip(blocks, occupancy, strict=True):
        times = [
            (a.timestamp(), b.timestamp(), a.timestamp() + seconds, b.timestamp() - seconds)
            for a, b in block.windows
        ]
        result.append(np.array(times, dtype=np.float64).reshape(-1))
    return result


def spans_of(grid: TimeGrid, occupancy: FloatArray) -> IntArray:
    """(n_blocks, n_slices): slices from edge ``i`` up to the first edge at or after ``i`` plus the
    block's occupancy (0 where that is past the night's end)."""
    starts = grid.edges[:-1][np.newaxis, :]
    ends = starts + occupancy.reshape(-1, 1)
    last = np.searchsorted(grid.edges, ends - 1e-6, side="left")
    spans = last - np.arange(grid.n_slices)[np.newaxis, :]
    return np.where(ends <= grid.end + 1e-6, spans, 0).astype(np.int64)


def meridian_crossings(
    grid: TimeGrid, site: Site, blocks: Sequence[SchedulableBlock], visible: BoolArray
) -> FloatArray:
    """1.0 for each block whose target crosses the meridian (hour angle 0, rising) in a slice where
    the block is visible, else 0.0 (J2000 coordinates: precession moves transits by a minute or so)."""
    lst = np.asarray(local_sidereal_time(grid.edges, site.longitude), dtype=np.float64)
    ras = np.array([[b.target.ra] for b in blocks], dtype=np.float64).reshape(len(blocks), 1)
    ha = (lst[np.newaxis, :] - ras + 180.0) % 360.0 - 180.0
    crossing = (ha[:, :-1] <= 0.0) & (ha[:, 1:] > 0.0)
    result: FloatArray = np.any(crossing & visible, axis=1).astype(np.float64)
    return result


def check_placement(problem: SchedulingProblem, starts: IntArray) -> None:
    """Raise if ``starts`` places a block where it cannot start or two blocks overlap (a solver bug)."""
    can_start = problem.can_start
    occupied = np.zeros(problem.grid.n_slices, dtype=np.int64)
    for row in np.flatnonzero(starts >= 0):
        start = int(starts[row])
        if not can_start[row, start]:
            block_id = problem.blocks[row].id
            raise RuntimeError(f"solver placed block {block_id!r} at slice {start}, where it is not visible")
        occupied[start : start + int(problem.spans[row, start])] += 1
    if np.any(occupied > 1):
        raise RuntimeError(f"solver placed overlapping blocks at slices {np.flatnonzero(occupied > 1)}")


def density_bound(problem: SchedulingProblem) -> float:
    """An upper bound on the objective of any schedule of the blocks, on any time grid or none.

    A placed block is worth ``priority x duration`` and holds the telescope for at least
    ``setup + duration`` (slews take >= 0 s), all of it while the block is visible. So no second of
    the night is worth more than the best ``priority x duration / (setup + duration)`` among the
    blocks visible then. It ignores that a block is observed once and every slew and rounding: a
    relaxation of the continuous problem, not of one grid. Visibility is the problem's, widened by
    one slice each way so that sampling it at slice edges cannot hide a visible moment.
    """
    if not problem.blocks or problem.grid.n_slices == 0:
        return 0.0
    visible = problem.visible.copy()
    visible[:, 1:] |= problem.visible[:, :-1]
    visible[:, :-1] |= problem.visible[:, 1:]
    per_second = problem.weights / np.array([b.setup_s + b.duration_s for b in problem.blocks])
    best = np.where(visible, per_second[:, np.newaxis], 0.0).max(axis=0)
    return float((best * problem.grid.durations).sum())
