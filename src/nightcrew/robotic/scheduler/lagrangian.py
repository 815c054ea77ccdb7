"""Fast good schedules for large instances: Lagrangian relaxation of "each block at most once".

Without that rule, the time-indexed problem is weighted interval scheduling on one telescope, which
a dynamic programme over the slices solves exactly in linear time. Prices ``mu[b]`` on using block
``b`` turn the rule into a penalty; for any prices ``>= 0``, ``DP(w - mu) + sum(mu)`` is an upper
bound, and subgradient steps on the prices drive the DP towards schedules that use every block at
most once. Each DP schedule is repaired (repeated blocks dropped) and its gaps filled greedily, which
gives the feasible schedules; the best one is improved by local search (an unused block goes in
where it is worth more than the blocks it pushes out). That schedule usually ends the search within
the MIP's gap at once (the MIP took 2-3 s a plan, most of a simulated night's CPU); otherwise it
bounds the MIP's kernel.
Pure numpy on the variable arrays of :mod:`~nightcrew.robotic.scheduler.mip`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = ["IntervalVariables", "LagrangianResult", "bounds_through", "lagrangian_schedule"]

IntArray = npt.NDArray[np.int64]
FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class IntervalVariables:
    """The MIP's variables: variable ``k`` starts block ``block_of[k]`` at slice ``start_of[k]``
    and occupies ``length_of[k]`` slices, worth ``value_of[k]``."""

    block_of: IntArray
    start_of: IntArray
    length_of: IntArray
    value_of: FloatArray
    n_blocks: int
    n_slices: int


def _backward(variables: IntervalVariables, values: FloatArray) -> tuple[FloatArray, IntArray]:
    """Best value of intervals from each slice edge to the end (blocks may repeat), and the variable
    starting each best tail (-1: the slice stays empty): DP over slices."""
    n = variables.n_slices
    best = np.zeros(n + 1)
    pick = np.full(n, -1, dtype=np.int64)
    order = np.argsort(variables.start_of, kind="stable")
    bounds = np.searchsorted(variables.start_of[order], np.arange(n + 1))
    ends = variables.start_of + variables.length_of
    for s in range(n - 1, -1, -1):
        best[s] = best[s + 1]
        here = order[bounds[s] : bounds[s + 1]]
        if len(here):
            totals = values[here] + best[ends[here]]
            top = int(np.argmax(totals))
            if totals[top] > best[s]:
                best[s], pick[s] = totals[top], here[top]
    return best, pick


def _forward(variables: IntervalVariables, values: FloatArray) -> FloatArray:
    """Best value of intervals from the start to each slice edge (the mirror of :func:`_backward`)."""
    n = variables.n_slices
    best = np.zeros(n + 1)
    ends = variables.start_of + variables.length_of
    order = np.argsort(ends, kind="stable")
    bounds = np.searchsorted(ends[order], np.arange(n + 2))
    for e in range(1, n + 1):
        best[e] = best[e - 1]
        here = order[bounds[e] : bounds[e + 1]]
        if len(here):
            best[e] = max(best[e], float(np.max(values[here] + best[variables.start_of[here]])))
    return best


def _best_intervals(variables: IntervalVariables, values: FloatArray) -> IntArray:
    """Variables of a max-value set of non-overlapping intervals (blocks may repeat)."""
    _, pick = _backward(variables, values)
    ends = variables.start_of + variables.length_of
    chosen = []
    s = 0
    while s < variables.n_slices:
        if pick[s] < 0:
            s += 1
        else:
            chosen.append(int(pick[s]))
            s = int(ends[pick[s]])
    return np.array(chosen, dtype=np.int64)


def bounds_through(variables: IntervalVariables, prices: FloatArray) -> FloatArray:
    """For every variable, an upper bound on the value of any schedule that uses it.

    A schedule uses each block at most once, so its value is at most ``sum(prices)`` plus its value
    at the prices ``value - prices[block]``; with the variable forced in, the best of the latter is
    the best path through it: forward DP to its start + its own + backward DP from its end.
    """
    values = variables.value_of - prices[variables.block_of]
    forward = _forward(variables, values)
    backward, _ = _backward(variables, values)
    ends = variables.start_of + variables.length_of
    return np.asarray(float(prices.sum()) + forward[variables.start_of] + values + backward[ends])


def _repair_and_fill(variables: IntervalVariables, chosen: IntArray, block_order: IntArray) -> IntArray:
    """Keep the most valuable use of every block, then add unused blocks where they fit (in
    ``block_order``, at their earliest free start)."""
    used = np.zeros(variables.n_blocks, dtype=np.bool_)
    busy = np.zeros(variables.n_slices, dtype=np.int64)
    kept = []
    for k in chosen[np.argsort(-variables.value_of[chosen], kind="stable")]:
        block = variables.block_of[k]
        if not used[block]:
            used[block] = True
            busy[variables.start_of[k] : variables.start_of[k] + variables.length_of[k]] = 1
            kept.append(int(k))
    # Variables are sorted by block (np.nonzero order): block b owns first[b]:first[b + 1].
    first = np.searchsorted(variables.block_of, np.arange(variables.n_blocks + 1))
    busy_before = np.concatenate([[0], np.cumsum(busy)])
    for block in block_order:
        if used[block] or first[block] == first[block + 1]:
            continue
        own = np.arange(first[block], first[block + 1])
        starts = variables.start_of[own]
        free = busy_before[starts + variables.length_of[own]] == busy_before[starts]
        if not free.any():
            continue
        k = int(own[np.argmax(free)])
        used[block] = True
        busy[variables.start_of[k] : variables.start_of[k] + variables.length_of[k]] = 1
        busy_before = np.concatenate([[0], np.cumsum(busy)])
        kept.append(k)
    return np.array(sorted(kept), dtype=np.int64)


def _improve(
    variables: IntervalVariables, chosen: IntArray, block_order: IntArray, *, passes: int = 20
) -> IntArray:
    """``chosen`` after local search: each unused block (in ``block_order``) takes its start where it
    gains most over the chosen variables it overlaps, which are dropped, if that gain is positive."""
    start, value, block = variables.start_of, variables.value_of, variables.block_of
    end = start + variables.length_of
    first = np.searchsorted(block, np.arange(variables.n_blocks + 1))
    chosen = np.sort(chosen)
    for _ in range(passes):
        improved = False
        for b in block_order:
            if first[b] == first[b + 1] or np.any(block[chosen] == b):
                continue
            own = np.arange(first[b], first[b + 1])
            overlaps = (start[own][:, None] < end[chosen][None, :]) & (
                start[chosen][None, :] < end[own][:, None]
            )
            gain = value[own] - overlaps @ value[chosen]
            best = int(np.argmax(gain))
            if gain[best] > 1e-9:
                chosen = np.sort(np.append(chosen[~overlaps[best]], own[best]))
                improved = True
        if not improved:
            break
    return chosen


@dataclass(frozen=True)
class LagrangianResult:
    """The best feasible variables found (``chosen``, worth ``value``), the best upper bound and
    the prices that gave it."""

    chosen: IntArray
    value: float
    bound: float
    prices: FloatArray


def lagrangian_schedule(
    variables: IntervalVariables, prices: FloatArray, *, iterations: int = 150
) -> LagrangianResult:
    """Subgradient search from ``prices``: good feasible schedules and an upper bound.

    Args:
        variables: The interval variables.
        prices: Starting prices per block (e.g. the LP duals of the "at most once" rows), >= 0.
        iterations: Subgradient steps.
    """
    value = variables.value_of
    first_var = np.searchsorted(variables.block_of, np.arange(variables.n_blocks))
    first_var = np.minimum(first_var, len(value) - 1)
    block_density = np.where(
        np.isin(np.arange(variables.n_blocks), variables.block_of),
        value[first_var] / variables.length_of[first_var],
        0.0,
    )
    block_order = np.argsort(-block_density, kind="stable")
    mu = np.maximum(0.0, prices.astype(np.float64).copy())
    best_vars = np.zeros(0, dtype=np.int64)
    best_value, upper = 0.0, np.inf
    best_mu = mu.copy()
    step_scale, stalled = 1.0, 0
    for _ in range(iterations):
        chosen = _best_intervals(variables, value - mu[variables.block_of])
        bound = float((value - mu[variables.block_of])[chosen].sum() + mu.sum())
        if bound < upper - 1e-9:
            upper, stalled, best_mu = bound, 0, mu.copy()
        else:
            stalled += 1
            if stalled >= 10:
                step_scale, stalled = step_scale / 2, 0
        feasible = _repair_and_fill(variables, chosen, block_order)
        feasible_value = float(value[feasible].sum())
        if feasible_value > best_value:
            best_vars, best_value = feasible, feasible_value
        uses = np.bincount(variables.block_of[chosen], minlength=variables.n_blocks)
        gradient = 1.0 - uses  # d(bound)/d(mu)
        norm = float(np.dot(gradient, gradient))
        if norm == 0 or upper - best_value <= 1e-6 * max(1.0, upper) or step_scale < 1e-4:
            break
        step = step_scale * (bound - best_value) / norm
        mu = np.maximum(0.0, mu - step * gradient)
    improved = _improve(variables, best_vars, block_order)
    if float(value[improved].sum()) > best_value:
        best_vars, best_value = improved, float(value[improved].sum())
    return LagrangianResult(best_vars, best_value, upper, best_mu)
