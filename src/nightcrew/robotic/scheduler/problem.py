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
        lengths: Slices each block occupies (overheads and duration, rounded up).
        weights: Value of placing each block: priority x observed hours.
        overhead_s: Seconds of overhead in front of each block's observation.
        flip_s: Seconds of meridian-flip allowance inside each block (0 where none may be needed).
    """

    grid: TimeGrid
    site: Site
    blocks: tuple[SchedulableBlock, ...]
    visible: BoolArray
    lengths: IntArray
    weights: FloatArray
    overhead_s: FloatArray
    flip_s: FloatArray

    @property
    def can_start(self) -> BoolArray:
        """(n_blocks, n_slices): starts whose whole occupancy is visible."""
        return startable(self.visible, self.lengths)


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
    slew_overhead_s: float,
    meridian_flip_s: float = 0.0,
    constraints: Sequence[Constraint] = DEFAULT_CONSTRAINTS,
) -> SchedulingProblem:
    """The grid form of ``blocks`` between Unix times ``start`` and ``end``."""
    if not slew_overhead_s >= 0:
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
    grid = TimeGrid.covering(start, end, step_s)
    sky = SkyGrid(grid, site, blocks)
    overhead = np.array([b.setup_s + slew_overhead_s for b in blocks], dtype=np.float64)
    visible = visibility(sky, constraints)
    flips = meridian_crossings(grid, site, blocks, visible) * meridian_flip_s
    lengths = np.array(
        [grid.slices_for(o + f + b.duration_s) for b, o, f in zip(blocks, overhead, flips, strict=True)],
        dtype=np.int64,
    )
    weights = np.array([b.priority * b.duration_s / 3600.0 for b in blocks], dtype=np.float64)
    return SchedulingProblem(
        grid=grid,
        site=site,
        blocks=tuple(blocks),
        visible=visible,
        lengths=lengths,
        weights=weights,
        overhead_s=overhead,
        flip_s=flips,
    )


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
        occupied[start : start + int(problem.lengths[row])] += 1
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
    return float(best.sum() * problem.grid.step)
