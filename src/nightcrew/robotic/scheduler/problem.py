"""One scheduling problem on arrays, shared by every solver, and a solver's answer.

:func:`build_problem` turns blocks and a night into the grid form both solvers read: which slices
each block may occupy (:func:`~nightcrew.robotic.scheduler.constraints.visibility`), how many slices
it occupies, and what placing it is worth. Solvers then only choose start slices, so the MIP and
the priority baseline are compared on exactly the same visibility, lengths and weights.

Overheads are modelled by padding: a block occupies ``setup_s + slew_overhead_s + duration_s``,
rounded up to whole slices, where ``slew_overhead_s`` is one worst-case slew (plus settling) for
every block. That over-estimates short slews between neighbours, but keeps every schedule
executable without transition variables (which would make the MIP quadratic in blocks).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.scheduler.blocks import SchedulableBlock
from nightcrew.robotic.scheduler.constraints import DEFAULT_CONSTRAINTS, Constraint, startable, visibility
from nightcrew.robotic.scheduler.sky import SkyGrid, TimeGrid
from nightcrew.site import Site

__all__ = ["Placement", "SchedulingProblem", "build_problem", "check_placement", "density_bound"]

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
    """

    grid: TimeGrid
    site: Site
    blocks: tuple[SchedulableBlock, ...]
    visible: BoolArray
    lengths: IntArray
    weights: FloatArray
    overhead_s: FloatArray

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
    constraints: Sequence[Constraint] = DEFAULT_CONSTRAINTS,
) -> SchedulingProblem:
    """The grid form of ``blocks`` between Unix times ``start`` and ``end``."""
    if not slew_overhead_s >= 0:
        raise InvalidArgumentError(f"slew_overhead_s must be >= 0, got {slew_overhead_s}")
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
    lengths = np.array(
        [grid.slices_for(o + b.duration_s) for b, o in zip(blocks, overhead, strict=True)], dtype=np.int64
    )
    weights = np.array([b.priority * b.duration_s / 3600.0 for b in blocks], dtype=np.float64)
    return SchedulingProblem(
        grid=grid,
        site=site,
        blocks=tuple(blocks),
        visible=visibility(sky, constraints),
        lengths=lengths,
        weights=weights,
        overhead_s=overhead,
    )


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
