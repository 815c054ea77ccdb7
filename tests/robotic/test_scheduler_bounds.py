"""Bounds of the scheduler and schedules on fine grids: every bound really bounds, every slot is feasible."""

from __future__ import annotations

import itertools
from datetime import UTC, datetime, timedelta

import numpy as np
import pytest

from nightcrew.astro import airmass, radec_to_altaz
from nightcrew.robotic.scheduler import Constraints, Night, SchedulableBlock, Scheduler, Target
from nightcrew.robotic.scheduler.lagrangian import IntervalVariables, bounds_through, lagrangian_schedule
from nightcrew.robotic.scheduler.mip import solve_time_indexed
from nightcrew.robotic.scheduler.problem import check_placement, density_bound
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
START = datetime(2024, 1, 15, 17, 0, tzinfo=UTC)
NIGHT = Night(START, START + timedelta(hours=13), SITE)
QUICK = 2.0


def random_variables(seed: int, n_blocks: int = 4, n_slices: int = 9) -> IntervalVariables:
    rng = np.random.default_rng(seed)
    can_start = rng.uniform(size=(n_blocks, n_slices)) < 0.5
    lengths = rng.integers(1, 4, size=n_blocks)
    can_start &= np.arange(n_slices)[np.newaxis, :] + lengths[:, np.newaxis] <= n_slices
    block_of, start_of = np.nonzero(can_start)
    weights = rng.uniform(1.0, 5.0, size=n_blocks)
    return IntervalVariables(
        block_of, start_of, lengths[block_of], weights[block_of] * lengths[block_of], n_blocks, n_slices
    )


def feasible_schedules(variables: IntervalVariables) -> list[tuple[int, ...]]:
    """Every set of variables using each block at most once without overlaps (brute force)."""
    found = []
    for size in range(len(variables.block_of) + 1):
        for chosen in itertools.combinations(range(len(variables.block_of)), size):
            blocks = variables.block_of[list(chosen)]
            if len(set(blocks.tolist())) < len(blocks):
                continue
            busy = np.zeros(variables.n_slices, dtype=np.int64)
            for k in chosen:
                busy[variables.start_of[k] : variables.start_of[k] + variables.length_of[k]] += 1
            if busy.max(initial=0) <= 1:
                found.append(chosen)
    return found


@pytest.mark.parametrize("seed", range(6))
def test_bounds_through_bound_every_schedule_using_a_variable(seed: int) -> None:
    variables = random_variables(seed)
    schedules = feasible_schedules(variables)
    best = max(float(variables.value_of[list(s)].sum()) for s in schedules)
    rng = np.random.default_rng(100 + seed)
    for prices in (np.zeros(variables.n_blocks), rng.uniform(0.0, 6.0, size=variables.n_blocks)):
        through = bounds_through(variables, prices)
        for k in range(len(variables.block_of)):
            using = [float(variables.value_of[list(s)].sum()) for s in schedules if k in s]
            assert max(using) <= through[k] + 1e-9
    result = lagrangian_schedule(variables, np.zeros(variables.n_blocks))
    assert tuple(sorted(result.chosen.tolist())) in schedules
    assert result.value == pytest.approx(float(variables.value_of[result.chosen].sum()))
    assert result.value <= best + 1e-9 <= result.bound + 2e-9


def test_without_the_lp_the_solver_keeps_a_valid_bound() -> None:
    problem = Scheduler().problem(synthetic_blocks(NIGHT, 60, seed=11), NIGHT)
    arrays = (problem.can_start, problem.spans, problem.weights)
    with_lp = solve_time_indexed(*arrays)
    without = solve_time_indexed(*arrays, lp_max_entries=0)
    check_placement(problem, without.starts)
    assert with_lp.bound is not None and without.bound is not None
    assert without.objective <= with_lp.bound + 1e-6
    assert without.bound >= with_lp.objective - 1e-6
    assert without.objective >= 0.98 * with_lp.objective


def test_the_density_bound_of_one_block_visible_all_night() -> None:
    anytime = Constraints(max_sun_altitude=90.0)
    blocks = [SchedulableBlock("a", 4.0, 1200.0, Target(60.0, 80.0), constraints=anytime, setup_s=300.0)]
    problem = Scheduler(step_s=600.0, slew_overhead_s=0.0).problem(blocks, NIGHT)
    assert problem.visible.all()
    # 13 h at 4 x 1200 / 1500 per hour
    assert density_bound(problem) == pytest.approx(13 * 4.0 * 1200 / 1500)


@pytest.mark.parametrize("step", [60.0, 300.0])
def test_the_density_bound_bounds_both_solvers(step: float) -> None:
    blocks = synthetic_blocks(NIGHT, 150, seed=12)
    upper = density_bound(Scheduler(step_s=60.0, slew_overhead_s=0.0).problem(blocks, NIGHT))
    mip = Scheduler(step_s=step)
    optimal = mip.solve(mip.problem(blocks, NIGHT))
    plain = Scheduler(solver="priority", step_s=step)
    greedy = plain.solve(plain.problem(blocks, NIGHT))
    assert optimal.objective <= upper
    assert greedy.objective <= upper
    assert optimal.objective >= greedy.objective - 1e-9


def test_a_fine_grid_schedule_is_feasible() -> None:
    # 60-s slices, windows, airmass limits and 60 s set-up + 100 s slew in front of every block.
    blocks = synthetic_blocks(NIGHT, 120, seed=13, window_fraction=0.5, constrained_fraction=0.5)
    by_id = {b.id: b for b in blocks}
    schedule = Scheduler(step_s=60.0, time_limit_s=QUICK).schedule(blocks, NIGHT)
    assert len(schedule.slots) > 10
    for earlier, later in itertools.pairwise(schedule.slots):
        assert earlier.end <= later.start
    for slot in schedule.slots:
        block = by_id[slot.task_id]
        occupied = (slot.end - slot.start).total_seconds()
        assert occupied == pytest.approx(block.setup_s + 100.0 + block.duration_s)
        assert NIGHT.start <= slot.start and slot.end <= NIGHT.end
        if block.windows:
            assert any(w_start <= slot.start and slot.end <= w_end for w_start, w_end in block.windows)
        for moment in (slot.start, slot.start + (slot.end - slot.start) / 2, slot.end):
            alt, _ = radec_to_altaz(
                block.target.ra, block.target.dec, SITE.latitude, SITE.longitude, moment.timestamp()
            )
            value = airmass(alt)
            assert value is not None and value <= block.constraints.max_airmass + 0.01
