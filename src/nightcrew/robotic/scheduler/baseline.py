"""The baseline: astroplan's greedy ``PriorityScheduler`` (the pyobs paper's scheduler) on our problem.

astroplan places blocks one by one in order of priority, each at the free time where its constraint
score is best. To compare algorithms rather than ephemerides, it sees exactly the MIP's problem:

* its time resolution is our slice length and its schedule spans our grid;
* each block's duration is its occupancy (overheads included, whole slices), so astroplan's
  rounding of durations to its resolution changes nothing;
* each block's only constraint is :class:`_PrecomputedVisibility`, our visibility row (astroplan
  adds its own "altitude > 0" on top, which our airmass limit implies anyway);
* astroplan's priority 1 is the most important, ours is a weight: we pass ``-priority``;
* astroplan's test for occupied grid points is replaced by an exact one (its float comparison lost
  one slice after every block, a handicap of ~9 % of the night that had nothing to do with greedy).

astroplan's "altitude > 0" needs Earth orientation data: we run it with astropy's bundled IERS
tables only (no download, degraded accuracy accepted), which is far better than a slice needs.
"""

from __future__ import annotations

import warnings
from typing import Any

import numpy as np

from nightcrew.robotic.scheduler.problem import Placement, SchedulingProblem

__all__ = ["solve_priority"]


def solve_priority(problem: SchedulingProblem) -> Placement:
    """Place the blocks as astroplan's PriorityScheduler does."""
    from astropy.utils import iers  # type: ignore[import-untyped]

    starts = np.full(len(problem.blocks), -1, dtype=np.int64)
    if not problem.blocks or problem.grid.n_slices == 0:
        return Placement(starts, 0.0, None, "done")
    with (
        iers.conf.set_temp("auto_download", False),
        iers.conf.set_temp("auto_max_age", None),
        iers.conf.set_temp("iers_degraded_accuracy", "ignore"),
        warnings.catch_warnings(),
    ):
        # astroplan's import warns when it finds no IERS-A table, which we decline on purpose.
        warnings.filterwarnings("ignore", message=".*IERS Bulletin A.*")
        placed = _run_astroplan(problem)
    grid = problem.grid
    row_of = {block.id: row for row, block in enumerate(problem.blocks)}
    for block_id, unix_start in placed.items():
        starts[row_of[block_id]] = round((unix_start - grid.start) / grid.step)
    objective = float(problem.weights[starts >= 0].sum())
    return Placement(starts, objective, None, "done")


def _run_astroplan(problem: SchedulingProblem) -> dict[str, float]:
    """Block id -> Unix start time of what astroplan scheduled."""
    import astropy.units as u  # type: ignore[import-untyped]
    from astroplan import (  # type: ignore[import-untyped]
        FixedTarget,
        Observer,
        ObservingBlock,
        Schedule,
        Transitioner,
    )
    from astropy.coordinates import EarthLocation, SkyCoord  # type: ignore[import-untyped]
    from astropy.time import Time  # type: ignore[import-untyped]

    grid, site = problem.grid, problem.site
    visibility_class = _precomputed_visibility_class()
    scheduler_class = _exact_priority_scheduler_class()
    location = EarthLocation.from_geodetic(
        site.longitude * u.deg, site.latitude * u.deg, site.elevation * u.m
    )
    observer = Observer(location=location)
    middle = grid.start + grid.step * grid.n_slices / 2
    blocks: list[Any] = []
    for row, block in enumerate(problem.blocks):
        ra, dec = block.target.position_at(middle)
        blocks.append(
            ObservingBlock(
                FixedTarget(SkyCoord(ra * u.deg, dec * u.deg), name=block.id),
                int(problem.lengths[row]) * grid.step * u.s,
                -block.priority,
                constraints=[visibility_class(problem.visible[row], grid.start, grid.step)],
                name=block.id,
            )
        )
    start = Time(grid.start, format="unix")
    end = Time(grid.start + grid.step * grid.n_slices, format="unix")
    schedule = Schedule(start, end)
    scheduler = scheduler_class(
        constraints=[], observer=observer, transitioner=Transitioner(), time_resolution=grid.step * u.s
    )
    scheduler(blocks, schedule)
    return {str(b.name): float(b.start_time.unix) for b in schedule.scheduled_blocks if b.name is not None}


def _precomputed_visibility_class() -> type[Any]:
    """An astroplan Constraint answering from our visibility row (made lazily: astroplan is optional
    at import time and pulls in much of astropy)."""
    from astroplan import Constraint

    class _PrecomputedVisibility(Constraint):  # type: ignore[misc]
        def __init__(self, visible: np.ndarray[Any, Any], grid_start: float, step: float) -> None:
            self.visible = visible
            self.grid_start = grid_start
            self.step = step

        def compute_constraint(self, times: Any, observer: Any, targets: Any) -> np.ndarray[Any, Any]:
            index = np.rint((np.asarray(times.unix) - self.grid_start) / self.step).astype(np.int64)
            inside = (index >= 0) & (index < len(self.visible))
            result = np.zeros(index.shape, dtype=bool)
            result[inside] = self.visible[index[inside]]
            return result

    return _PrecomputedVisibility


def _exact_priority_scheduler_class() -> type[Any]:
    """astroplan's PriorityScheduler with exact bookkeeping of the grid points blocks occupy.

    astroplan finds occupied grid points by comparing its time grid (one float JD per point) with
    each block's exact start and end. The grid point at a block's end comes out ~0.1 ms early, so
    it counts as occupied and one slice after every block is lost (1.2 h in a 13-h night of 14
    blocks). Every placed block knows the grid indices it holds (``start_idx``, ``end_idx``, set
    by astroplan itself): we mark those, which is what the comparison meant to do.
    """
    from astroplan import ObservingBlock, PriorityScheduler

    class _ExactPriorityScheduler(PriorityScheduler):  # type: ignore[misc]
        def _get_filled_indices(self, times: Any) -> np.ndarray[Any, Any]:
            is_open = np.ones(len(times), dtype=bool)
            for block in self.schedule.scheduled_blocks:
                if isinstance(block, ObservingBlock):
                    is_open[block.start_idx : block.end_idx] = False
            return is_open

    return _ExactPriorityScheduler
