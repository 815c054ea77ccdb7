"""The scheduler: blocks and a night in, a schedule out, by the MIP (default) or astroplan's greedy.

Re-planning is the same call with the current time: ``schedule(blocks, night, now=..., exclude=done
| failed, in_progress=slot)`` plans only what is left, from ``now`` (or the end of the block in
progress) to the end of the night. Times are always passed in; nothing here reads a clock.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Collection, Mapping, Sequence
from datetime import UTC, datetime, timedelta
from typing import Literal

import numpy as np
import numpy.typing as npt

from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.scheduler.baseline import solve_priority
from nightcrew.robotic.scheduler.blocks import Night, SchedulableBlock, Schedule
from nightcrew.robotic.scheduler.constraints import DEFAULT_CONSTRAINTS, Constraint
from nightcrew.robotic.scheduler.mip import solve_time_indexed
from nightcrew.robotic.scheduler.problem import Placement, SchedulingProblem, build_problem, check_placement
from nightcrew.robotic.scheduler.sequence import TYPICAL_QUANTILES, least_transitions, sequence
from nightcrew.robotic.scheduler.slew import Pointing, SlewModel
from nightcrew.robotic.scheduler.why import NIGHT_OVER, unplanned_reasons

__all__ = ["SOLVERS", "Scheduler"]

SolverName = Literal["mip", "priority"]
#: The solvers to choose from by name.
SOLVERS: tuple[SolverName, ...] = ("mip", "priority")


class Scheduler:
    """Plans a night.

    Args:
        solver: ``"mip"`` (optimal time-indexed MIP, HiGHS) or ``"priority"`` (astroplan's greedy).
        step_s: Length of a coarse time slice in seconds. The MIP refines the grid around windows
            (a block may also start at a window's opening or at its latest start in it, and the
            slices end there), so no window is lost to the step; the priority solver keeps it plain.
        slew_overhead_s: Worst-case slew plus settling added in front of every block (without a
            ``slew`` model).
        slew: The telescope's slew model: then every transition is priced exactly from the block
            before (:mod:`.sequence`), and the solver's allowance per block is the least
            transition into it, which keeps its bound valid.
        meridian_flip_s: Time a meridian flip takes (slew through the pole, re-centring, guiding
            again), added to every block whose target may cross the meridian in it; 0: no flips.
        time_limit_s: Accepted for configuration files written for earlier versions; it decides
            nothing: the MIP's work is limited by ``node_limit`` (deterministic, not wall time).
        node_limit: Most branch-and-bound nodes HiGHS explores on the kernel of useful variables;
            0 (the default): the Lagrangian schedule and its proven bound, without HiGHS's search.
        mip_rel_gap: The MIP stops once within this fraction of its proven bound.
        constraints: Constraint callables; by default those the blocks' Constraints and windows ask for.
    """

    def __init__(
        self,
        *,
        solver: SolverName = "mip",
        step_s: float = 300.0,
        slew_overhead_s: float = 100.0,
        meridian_flip_s: float = 0.0,
        time_limit_s: float = 10.0,
        node_limit: int = 0,
        mip_rel_gap: float = 5e-3,
        constraints: Sequence[Constraint] = DEFAULT_CONSTRAINTS,
        slew: SlewModel | None = None,
    ) -> None:
        if solver not in SOLVERS:
            raise InvalidArgumentError(f"solver must be one of {', '.join(SOLVERS)}, got {solver!r}")
        if not step_s > 0:
            raise InvalidArgumentError(f"step_s must be > 0, got {step_s}")
        if not slew_overhead_s >= 0:
            raise InvalidArgumentError(f"slew_overhead_s must be >= 0, got {slew_overhead_s}")
        if not meridian_flip_s >= 0:
            raise InvalidArgumentError(f"meridian_flip_s must be >= 0, got {meridian_flip_s}")
        if not time_limit_s > 0:
            raise InvalidArgumentError(f"time_limit_s must be > 0, got {time_limit_s}")
        if not node_limit >= 0:
            raise InvalidArgumentError(f"node_limit must be >= 0, got {node_limit}")
        if not 0 <= mip_rel_gap < 1:
            raise InvalidArgumentError(f"mip_rel_gap must be within 0..1, got {mip_rel_gap}")
        self.solver: SolverName = solver
        self.step_s = step_s
        self.slew_overhead_s = slew_overhead_s
        self.meridian_flip_s = meridian_flip_s
        self.time_limit_s = time_limit_s
        self.node_limit = node_limit
        self.mip_rel_gap = mip_rel_gap
        self.constraints = tuple(constraints)
        self.slew = slew

    def problem(
        self,
        blocks: Sequence[SchedulableBlock],
        night: Night,
        *,
        start: datetime | None = None,
        quantile: float = 0.0,
    ) -> SchedulingProblem:
        """The grid form of ``blocks`` from ``start`` (default: the night's start) to the night's end;
        with a slew model each block's allowance is the least transition into it (or ``quantile``)."""
        begin = night.start if start is None else max(night.start, start)
        slews: float | npt.NDArray[np.float64] = self.slew_overhead_s
        if self.slew is not None:
            samples = np.linspace(begin.timestamp(), night.end.timestamp(), 5)
            slews = least_transitions(self.slew, night.site, blocks, list(samples), quantile=quantile)
        return build_problem(
            blocks,
            night.site,
            begin.timestamp(),
            night.end.timestamp(),
            step_s=self.step_s,
            slew_overhead_s=slews,
            meridian_flip_s=self.meridian_flip_s,
            constraints=self.constraints,
            refine=self.solver == "mip",
        )

    def solve(self, problem: SchedulingProblem) -> Placement:
        """Choose start slices with the configured solver."""
        solvers: dict[SolverName, Callable[[SchedulingProblem], Placement]] = {
            "mip": self._solve_mip,
            "priority": solve_priority,
        }
        placement = solvers[self.solver](problem)
        check_placement(problem, placement.starts)
        return placement

    def _solve_mip(self, problem: SchedulingProblem) -> Placement:
        return solve_time_indexed(
            problem.can_start,
            problem.spans,
            problem.start_values(),
            node_limit=self.node_limit,
            mip_rel_gap=self.mip_rel_gap,
        )

    def schedule(
        self,
        blocks: Sequence[SchedulableBlock],
        night: Night,
        *,
        now: datetime | None = None,
        exclude: Collection[str] = (),
        in_progress: PlannedSlot | None = None,
        begin_at: Pointing | None = None,
    ) -> Schedule:
        """Plan the (rest of the) night.

        Args:
            blocks: Every block that could be observed; not modified.
            night: The night to fill.
            now: Plan from this time on (default: the night's start).
            exclude: Ids of blocks not to plan again (done, failed, cancelled).
            in_progress: The slot being observed now: kept first, and planning starts at its end.
            begin_at: Where the telescope points when the plan begins (with a slew model: the first
                slew is counted from there; None: not counted).
        """
        began = time.perf_counter()
        start, candidates = _remaining(blocks, night, now, exclude, in_progress)
        kept = (in_progress,) if in_progress is not None else ()
        if start >= night.end:
            return Schedule(kept, 0.0, 0.0, self.solver, time.perf_counter() - began, "night over")
        problem = self.problem(candidates, night, start=start)
        placement = self.solve(problem)
        slots, objective = _slots(problem, placement), placement.objective
        if self.slew is not None:
            plans = [_sequenced(problem, placement, self.slew, begin_at)]
            for quantile in TYPICAL_QUANTILES:
                typical = self.problem(candidates, night, start=start, quantile=quantile)
                placed = solve_time_indexed(
                    typical.can_start,
                    typical.spans,
                    typical.start_values(),
                    node_limit=self.node_limit,
                    lp_max_entries=0,
                )
                plans.append(_sequenced(typical, placed, self.slew, begin_at))
            slots, objective = max(plans, key=lambda plan: plan[1])  # the first of equals
        return Schedule(
            slots=kept + slots,
            objective=objective,
            bound=placement.bound,
            solver=self.solver,
            wall_time_s=time.perf_counter() - began,
            status=placement.status,
        )

    def explain(
        self,
        blocks: Sequence[SchedulableBlock],
        night: Night,
        schedule: Schedule,
        *,
        now: datetime | None = None,
        exclude: Collection[str] = (),
        in_progress: PlannedSlot | None = None,
        names: Mapping[str, str] | None = None,
    ) -> dict[str, str]:
        """Block id → why it is not in ``schedule``, for every block of ``blocks`` that may still be
        planned and is not (see :mod:`.why`); the arguments are those ``schedule`` was made with."""
        start, candidates = _remaining(blocks, night, now, exclude, in_progress)
        planned = {slot.task_id for slot in schedule.slots}
        if all(b.id in planned for b in candidates):
            return {}  # the common case: no second look at the sky
        if start >= night.end:
            return {b.id: NIGHT_OVER for b in candidates if b.id not in planned}
        return unplanned_reasons(
            self.problem(candidates, night, start=start),
            schedule.slots,
            self.constraints,
            names=names,
            priorities={b.id: b.priority for b in blocks},
        )


def _remaining(
    blocks: Sequence[SchedulableBlock],
    night: Night,
    now: datetime | None,
    exclude: Collection[str],
    in_progress: PlannedSlot | None,
) -> tuple[datetime, list[SchedulableBlock]]:
    """Where planning starts, and the blocks it may place."""
    start = night.start if now is None else max(night.start, now)
    if in_progress is not None:
        start = max(start, in_progress.end)
    skip = set(exclude) | ({in_progress.task_id} if in_progress is not None else set())
    return start, [b for b in blocks if b.id not in skip]


def _slots(problem: SchedulingProblem, placement: Placement) -> tuple[PlannedSlot, ...]:
    """The placed blocks as time slots, by start; a slot ends when its observation does."""
    slots = []
    occupancy = problem.occupancy_s  # summed as the grid's window edges were
    for row in np.flatnonzero(placement.starts >= 0):
        block = problem.blocks[row]
        begin = float(problem.grid.edges[placement.starts[row]])
        end = begin + float(occupancy[row])
        slots.append(PlannedSlot(block.id, _utc(begin), _utc(end)))
    return tuple(sorted(slots, key=lambda slot: slot.start))


def _sequenced(
    problem: SchedulingProblem, placement: Placement, model: SlewModel, begin_at: Pointing | None
) -> tuple[tuple[PlannedSlot, ...], float]:
    """The placement with exact transitions (:func:`.sequence.sequence`) as slots, and its value."""
    sequenced = sequence(problem, placement.starts, model, begin_at=begin_at)
    slots = tuple(PlannedSlot(problem.blocks[s.row].id, _utc(s.start), _utc(s.end)) for s in sequenced)
    values = problem.start_values()
    return slots, float(sum(values[s.row, max(0, problem.grid.index_at(s.start))] for s in sequenced))


def _utc(unix_time: float) -> datetime:
    return datetime(1970, 1, 1, tzinfo=UTC) + timedelta(seconds=unix_time)
