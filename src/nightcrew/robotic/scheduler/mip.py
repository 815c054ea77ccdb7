"""The optimal scheduler: a time-indexed mixed-integer program, solved by HiGHS through scipy.

Model (all on the slice grid of :mod:`~nightcrew.robotic.scheduler.sky`):

* variables: binary ``x[b, t]`` = block ``b`` starts at slice ``t``; only created where the block's
  whole occupancy (``lengths[b]`` slices: overhead + duration, rounded up) is visible;
* each block at most once: ``sum_t x[b, t] <= 1``;
* no overlap: for a slice ``s``, the blocks occupying it sum to <= 1. Intervals have the Helly
  property (pairwise overlapping intervals share a point, namely the latest start), so rows are
  needed only at slices where some variable starts;
* objective: maximise ``sum weights[b] * x[b, t]`` (the caller passes priority x observed hours).

Solving it plainly, HiGHS often spends many seconds in root cuts on a few thousand
variables without a good schedule (scipy cannot hand it a starting solution). So the search runs in
three steps, each keeping a proven upper bound:

1. the LP relaxation gives prices on the "each block once" rows and the LP bound. On fine grids
   (more than ``lp_max_entries`` matrix entries, or ``lp_max_iterations`` simplex steps) the LP takes
   too long; then the prices start at zero, which costs the next step a
   few more iterations but gives the same bound to 0.1 %;
2. :func:`~nightcrew.robotic.scheduler.lagrangian.lagrangian_schedule` turns the prices into a good
   schedule (``incumbent``, typically > 99 % of the bound), a Lagrangian bound and its prices
   ``mu``; if the gap is already below ``mip_rel_gap``, that is the answer;
3. at prices ``mu`` every schedule using variable ``k`` scores at most ``sum(mu)`` plus the best
   path through ``k`` (:func:`~nightcrew.robotic.scheduler.lagrangian.bounds_through`), so
   variables whose bound is below the incumbent are useless. The MIP runs on the others (at most
   ``kernel_size``, best bound first); when none was left out, HiGHS's dual bound
   (``OptimizeResult.mip_dual_bound``) holds for the whole problem.

Pure and deterministic: arrays in, arrays out; no clock, no I/O. Every limit counts work (steps,
variables, nodes), so a busy machine gets the same plan later, not a different one.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from scipy.optimize import LinearConstraint, linprog, milp  # type: ignore[import-untyped]
from scipy.sparse import csr_array  # type: ignore[import-untyped]

from nightcrew.robotic.scheduler.lagrangian import IntervalVariables, bounds_through, lagrangian_schedule
from nightcrew.robotic.scheduler.problem import Placement

__all__ = ["solve_time_indexed"]

IntArray = npt.NDArray[np.int64]
FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]

_STATUS = {0: "optimal", 1: "limit reached", 2: "infeasible", 3: "unbounded", 4: "solver error"}


def solve_time_indexed(
    can_start: BoolArray,
    lengths: IntArray,
    weights: FloatArray,
    *,
    node_limit: int = 0,
    mip_rel_gap: float = 5e-3,
    kernel_size: int = 4000,
    lp_max_entries: int = 800_000,
    lp_max_iterations: int = 20_000,
) -> Placement:
    """Choose start slices maximising the weight of the placed blocks without overlaps.

    The work is limited by counts (subgradient steps, kernel variables, branch-and-bound nodes),
    never by the clock: the same arrays give the same schedule on a quiet and on a busy machine.

    Args:
        can_start: (n_blocks, n_slices): where each block may start.
        lengths: Slices each block occupies once started (>= 1): per block (n_blocks,) or per block
            and start (n_blocks, n_slices).
        weights: Value of placing each block (> 0): per block (n_blocks,) or per block and start
            (n_blocks, n_slices), e.g. with an early-start term.
        node_limit: Most branch-and-bound nodes HiGHS explores (step 3 above); 0 leaves step 3 out.
            Even one node costs HiGHS its root LP and cuts on the kernel (5 s on 4,000 variables
            on a busy machine), which rarely beats step 2 by more than its gap: the scheduler
            leaves it out by default.
        mip_rel_gap: Stop when (bound - objective) / bound is below this.
        kernel_size: Most variables handed to the MIP (step 3 above).
        lp_max_entries: Largest no-overlap matrix (non-zero entries) whose LP gives the first
            prices (step 1 above).
        lp_max_iterations: Most simplex iterations of that LP (a count, not a time); an LP that
            needs more leaves the prices at zero, as a too large one does.
    """
    n_blocks, n_slices = can_start.shape
    block_of, start_of = np.nonzero(can_start)
    starts = np.full(n_blocks, -1, dtype=np.int64)
    if len(block_of) == 0:
        return Placement(starts, 0.0, 0.0, "optimal")
    spans = np.broadcast_to(lengths.reshape(n_blocks, -1), (n_blocks, n_slices))
    values = np.broadcast_to(weights.reshape(n_blocks, -1), (n_blocks, n_slices))
    variables = IntervalVariables(
        block_of, start_of, spans[block_of, start_of], values[block_of, start_of], n_blocks, n_slices
    )
    chosen, objective, bound, status = _solve(
        variables, kernel_size, node_limit, mip_rel_gap, lp_max_entries, lp_max_iterations
    )
    starts[block_of[chosen]] = start_of[chosen]
    return Placement(starts, objective, max(objective, bound), status)


def _solve(
    variables: IntervalVariables,
    kernel_size: int,
    node_limit: int,
    mip_rel_gap: float,
    lp_max_entries: int,
    lp_max_iterations: int,
) -> tuple[IntArray, float, float, str]:
    """Chosen variables, their value, a proven upper bound and a status (steps 1-3 of the module)."""
    costs = variables.value_of
    prices, lp_bound = np.zeros(variables.n_blocks), np.inf
    if int(variables.length_of.sum()) <= lp_max_entries:
        matrix = _constraint_matrix(variables, np.arange(len(costs)))
        ones = np.ones(matrix.shape[0])
        relaxation = linprog(
            -costs,
            A_ub=matrix,
            b_ub=ones,
            bounds=(0, 1),
            method="highs",
            options={"maxiter": lp_max_iterations},
        )
        if relaxation.status == 0:  # else (never seen) the prices stay at zero
            row_prices = np.maximum(0.0, -np.asarray(relaxation.ineqlin.marginals))
            reduced = matrix.T @ row_prices - costs
            # Weak duality: valid for any prices >= 0, whatever the LP's tolerances.
            lp_bound = float(row_prices.sum() + np.maximum(0.0, -reduced).sum())
            prices = row_prices[: variables.n_blocks]
    lagrangian = lagrangian_schedule(variables, prices)
    best, incumbent = lagrangian.chosen, lagrangian.value
    upper = min(lp_bound, lagrangian.bound)
    if upper - incumbent <= mip_rel_gap * upper:
        return best, incumbent, upper, "optimal"

    if node_limit <= 0:  # no branch and bound: the Lagrangian schedule and the bound as they are
        return best, incumbent, upper, "work limit reached"
    through = bounds_through(variables, lagrangian.prices)
    useful = np.flatnonzero(through >= incumbent - 1e-9)
    kernel = useful[np.argsort(-through[useful], kind="stable")[:kernel_size]]
    chosen, objective, kernel_bound, status = _solve_mip(
        _constraint_matrix(variables, kernel), costs[kernel], node_limit, mip_rel_gap
    )
    if objective > incumbent:
        best, incumbent = kernel[chosen], objective
    if len(kernel) == len(useful):  # every variable left out is proven useless
        return best, incumbent, min(upper, max(incumbent, kernel_bound)), status
    return best, incumbent, upper, "limit reached" if status == "optimal" else status


def _solve_mip(
    matrix: csr_array, costs: FloatArray, node_limit: int, mip_rel_gap: float
) -> tuple[IntArray, float, float, str]:
    """Chosen variables, objective, HiGHS's dual bound and status of max costs.x, matrix.x <= 1."""
    result = milp(
        c=-costs,
        integrality=np.ones(len(costs)),
        bounds=(0, 1),
        constraints=LinearConstraint(matrix, -np.inf, 1.0),
        options={"node_limit": int(node_limit), "mip_rel_gap": float(mip_rel_gap), "presolve": True},
    )
    status = _STATUS.get(int(result.status), f"status {result.status}")
    bound = float(-result.mip_dual_bound) if result.mip_dual_bound is not None else float(costs.sum())
    if result.x is None:  # limit reached before any feasible point: the empty schedule is feasible
        return np.zeros(0, dtype=np.int64), 0.0, bound, status
    chosen = np.flatnonzero(result.x > 0.5)
    return chosen, float(costs[chosen].sum()), bound, status


def _constraint_matrix(variables: IntervalVariables, columns: IntArray) -> csr_array:
    """The rows of the variables ``columns``: 0..n_blocks-1 each block once; then one no-overlap row
    per slice where one of them starts."""
    block_of, start_of = variables.block_of[columns], variables.start_of[columns]
    var_lengths = variables.length_of[columns]
    n_vars, n_blocks = len(columns), variables.n_blocks
    # One entry per (variable, occupied slice): slice = start + 0, 1, ..., length - 1.
    var_of_entry = np.repeat(np.arange(n_vars), var_lengths)
    first_entry = np.cumsum(var_lengths) - var_lengths
    offset = np.arange(len(var_of_entry)) - np.repeat(first_entry, var_lengths)
    slice_of_entry = start_of[var_of_entry] + offset

    start_slices = np.unique(start_of)
    row_of_slice = np.full(variables.n_slices, -1, dtype=np.int64)
    row_of_slice[start_slices] = n_blocks + np.arange(len(start_slices))
    overlap_rows = row_of_slice[slice_of_entry]
    keep = overlap_rows >= 0

    rows = np.concatenate([block_of, overlap_rows[keep]])
    cols = np.concatenate([np.arange(n_vars), var_of_entry[keep]])
    data = np.ones(len(rows))
    return csr_array((data, (rows, cols)), shape=(n_blocks + len(start_slices), n_vars))
