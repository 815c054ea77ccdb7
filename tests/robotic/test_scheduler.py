"""The scheduler core: visibility, feasibility, optimality against hand-made optima and the greedy."""

from __future__ import annotations

import copy
from datetime import UTC, datetime, timedelta

import numpy as np
import pytest

from nightcrew.astro import radec_to_altaz, sun_altitude
from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.scheduler import (
    Constraints,
    Night,
    SchedulableBlock,
    Schedule,
    Scheduler,
    SkyGrid,
    Target,
    TimeGrid,
)
from nightcrew.robotic.scheduler.constraints import altitude_for_airmass
from nightcrew.robotic.scheduler.mip import solve_time_indexed
from nightcrew.robotic.scheduler.problem import check_placement
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
START = datetime(2024, 1, 15, 17, 0, tzinfo=UTC)  # the Sun is below -12° from 17:00 to 06:00 UTC
NIGHT = Night(START, START + timedelta(hours=13), SITE)
CIRCUMPOLAR = Target(ra=60.0, dec=80.0)  # airmass < 1.5 all night at this latitude
#: Tests stop the MIP early: HiGHS may take its whole limit to prove the last half per cent.
QUICK = 2.0


def block(name: str, **kwargs: object) -> SchedulableBlock:
    values: dict[str, object] = {"priority": 1.0, "duration_s": 1800.0, "target": CIRCUMPOLAR}
    values.update(kwargs)
    return SchedulableBlock(id=name, **values)  # type: ignore[arg-type]


def hours(h: float) -> datetime:
    return START + timedelta(hours=h)


def assert_no_overlap(schedule: Schedule) -> None:
    for earlier, later in zip(schedule.slots, schedule.slots[1:], strict=False):
        assert earlier.end <= later.start, f"{earlier} overlaps {later}"


# --- visibility -----------------------------------------------------------------------------------


def test_altitudes_agree_with_the_telescope_coordinates() -> None:
    grid = TimeGrid.covering(START.timestamp(), NIGHT.end.timestamp(), 3600.0)
    blocks = [block("a", target=Target(83.8, -5.4)), block("b", target=Target(310.0, 45.0))]
    sky = SkyGrid(grid, SITE, blocks)
    for row, b in enumerate(blocks):
        for column, t in enumerate(sky.edges):
            alt, _ = radec_to_altaz(b.target.ra, b.target.dec, SITE.latitude, SITE.longitude, float(t))
            assert sky.altitude[row, column] == pytest.approx(alt, abs=0.05)


def test_a_target_below_the_airmass_limit_is_never_scheduled() -> None:
    blocks = [
        block("southern", target=Target(83.8, -60.0)),  # never rises at +51.6°
        block("too-low", target=Target(83.8, -5.4), constraints=Constraints(max_airmass=1.2)),  # max alt 33°
        block("fine", target=Target(83.8, -5.4)),
    ]
    schedule = Scheduler().schedule(blocks, NIGHT)
    assert [s.task_id for s in schedule.slots] == ["fine"]
    slot = schedule.slots[0]
    for moment in (slot.start, slot.end):
        alt, _ = radec_to_altaz(83.8, -5.4, SITE.latitude, SITE.longitude, moment.timestamp())
        assert alt >= altitude_for_airmass(2.0) - 0.05


def test_blocks_wait_for_the_sun_to_set() -> None:
    afternoon = Night(datetime(2024, 1, 15, 13, 0, tzinfo=UTC), START + timedelta(hours=3), SITE)
    blocks = [
        block(f"b{i}", duration_s=900.0, constraints=Constraints(max_sun_altitude=-18.0)) for i in range(4)
    ]
    schedule = Scheduler().schedule(blocks, afternoon)
    assert len(schedule.slots) == 4
    for slot in schedule.slots:
        for moment in (slot.start, slot.end):
            assert sun_altitude(SITE.latitude, SITE.longitude, moment.timestamp()) <= -18.0 + 0.05


def test_observation_windows_are_respected() -> None:
    window = (hours(5.0), hours(6.5))
    blocks = [block("windowed", priority=5.0, windows=(window,))] + [block(f"other{i}") for i in range(30)]
    schedule = Scheduler().schedule(blocks, NIGHT)
    slot = next(s for s in schedule.slots if s.task_id == "windowed")
    assert window[0] <= slot.start and slot.end <= window[1]
    assert_no_overlap(schedule)


def test_moon_constraints_exclude_blocks() -> None:
    # Mid-January 2024 the Moon is a waxing crescent, lit ~20 %, in Aquarius/Pisces.
    blocks = [
        block("dark-only", constraints=Constraints(max_moon_illumination=0.05)),
        block("fine", constraints=Constraints(max_moon_illumination=0.5, min_moon_distance=30.0)),
    ]
    schedule = Scheduler().schedule(blocks, NIGHT)
    assert [s.task_id for s in schedule.slots] == ["fine"]


# --- optimality -----------------------------------------------------------------------------------


def test_the_mip_finds_the_optimum_of_a_greedy_trap_on_arrays() -> None:
    # One valuable block fills the night; two cheaper ones fit side by side and are worth more.
    can_start = np.zeros((3, 10), dtype=np.bool_)
    can_start[0, 0] = True
    can_start[1, :6] = True
    can_start[2, :6] = True
    placement = solve_time_indexed(can_start, np.array([10, 5, 5]), np.array([10.0, 6.0, 6.0]))
    assert placement.starts[0] == -1
    assert sorted(placement.starts[1:].tolist()) == [0, 5]
    assert placement.objective == pytest.approx(12.0)
    assert placement.bound == pytest.approx(12.0)


def test_mip_beats_astroplan_in_a_greedy_trap() -> None:
    # A (priority 10, 1 h) must sit between 6 h and 7 h; B and C (priority 5, 6 h each) must lie in the
    # first and second half. Priority order places A first and loses B or C; the MIP leaves A out.
    blocks = [
        block("A", priority=10.0, duration_s=3600.0, windows=((hours(6.0), hours(7.0)),)),
        block("B", priority=5.0, duration_s=6 * 3600.0, windows=((hours(0.0), hours(6.5)),)),
        block("C", priority=5.0, duration_s=6 * 3600.0, windows=((hours(6.5), hours(13.0)),)),
    ]
    optimal = Scheduler(slew_overhead_s=0.0).schedule(blocks, NIGHT)
    greedy = Scheduler(solver="priority", slew_overhead_s=0.0).schedule(blocks, NIGHT)
    assert sorted(s.task_id for s in optimal.slots) == ["B", "C"]
    assert optimal.objective == pytest.approx(60.0)
    assert optimal.bound == pytest.approx(60.0)
    assert "A" in {s.task_id for s in greedy.slots}
    assert greedy.objective <= 40.0  # A and at most one of B, C


@pytest.mark.parametrize("seed", [3, 4])
def test_mip_is_at_least_as_good_as_the_greedy_on_random_nights(seed: int) -> None:
    blocks = synthetic_blocks(NIGHT, 40, seed=seed)
    mip = Scheduler()
    problem = mip.problem(blocks, NIGHT)
    optimal = mip.solve(problem)
    plain = Scheduler(solver="priority")
    greedy_problem = plain.problem(blocks, NIGHT)  # astroplan's grid stays plain
    greedy = plain.solve(greedy_problem)
    check_placement(greedy_problem, greedy.starts)
    assert optimal.bound is not None and optimal.objective <= optimal.bound + 1e-9
    assert optimal.objective >= greedy.objective - 1e-9


def test_the_kernel_path_keeps_a_valid_bound_and_a_good_schedule() -> None:
    problem = Scheduler().problem(synthetic_blocks(NIGHT, 120, seed=5), NIGHT)
    arrays = (problem.can_start, problem.spans, problem.weights)
    full = solve_time_indexed(*arrays)  # the Lagrangian schedule and bound, no branch and bound
    kernel = solve_time_indexed(*arrays, node_limit=20, mip_rel_gap=1e-4, kernel_size=300)
    check_placement(problem, kernel.starts)
    assert full.bound is not None and kernel.bound is not None
    assert kernel.objective <= full.bound + 1e-6  # nothing beats the proven optimum ...
    assert kernel.bound >= full.objective - 1e-6  # ... and the kernel's bound really bounds
    assert kernel.objective >= 0.98 * full.objective


def test_no_overlaps_and_the_objective_adds_up() -> None:
    blocks = synthetic_blocks(NIGHT, 60, seed=6)
    schedule = Scheduler(time_limit_s=QUICK).schedule(blocks, NIGHT)
    assert_no_overlap(schedule)
    by_id = {b.id: b for b in blocks}
    expected = sum(by_id[s.task_id].priority * by_id[s.task_id].duration_s / 3600 for s in schedule.slots)
    assert schedule.objective == pytest.approx(expected)
    assert all(NIGHT.start <= s.start and s.end <= NIGHT.end for s in schedule.slots)


# --- re-planning ----------------------------------------------------------------------------------


def test_replanning_excludes_done_blocks_and_starts_now() -> None:
    blocks = synthetic_blocks(NIGHT, 40, seed=7)
    scheduler = Scheduler(time_limit_s=QUICK)
    first = scheduler.schedule(blocks, NIGHT)
    done = {s.task_id for s in first.slots[:2]}
    failed = first.slots[2].task_id
    running = PlannedSlot(first.slots[3].task_id, hours(3.0), hours(3.4))
    now = hours(3.0)
    again = scheduler.schedule(blocks, NIGHT, now=now, exclude=done | {failed}, in_progress=running)
    assert again.slots[0] == running
    ids = [s.task_id for s in again.slots]
    assert not (done | {failed}) & set(ids)
    assert ids.count(running.task_id) == 1
    assert all(s.start >= running.end for s in again.slots[1:])
    assert_no_overlap(again)


def test_planning_after_the_night_returns_an_empty_schedule() -> None:
    schedule = Scheduler().schedule([block("a")], NIGHT, now=NIGHT.end + timedelta(minutes=1))
    assert schedule.slots == () and schedule.status == "night over"


def test_input_blocks_are_not_modified() -> None:
    blocks = synthetic_blocks(NIGHT, 20, seed=8)
    before = copy.deepcopy(blocks)
    Scheduler(time_limit_s=QUICK).schedule(blocks, NIGHT)
    Scheduler(solver="priority").schedule(blocks, NIGHT)
    assert blocks == before


# --- bad input ------------------------------------------------------------------------------------


def test_bad_blocks_name_the_block_and_the_field() -> None:
    with pytest.raises(InvalidArgumentError, match="block 'x': priority must be > 0"):
        block("x", priority=0.0)
    with pytest.raises(InvalidArgumentError, match="block 'x': duration_s must be > 0"):
        block("x", duration_s=-5.0)
    with pytest.raises(InvalidArgumentError, match="block 'x': max_airmass must be >= 1"):
        block("x", constraints=Constraints(max_airmass=0.5))
    with pytest.raises(InvalidArgumentError, match="block 'x': window start must be an aware datetime"):
        block("x", windows=((datetime(2024, 1, 15, 20), datetime(2024, 1, 15, 21)),))
    with pytest.raises(InvalidArgumentError, match=r"block 'x': window start .* is not before its end"):
        block("x", windows=((hours(2), hours(1)),))


def test_bad_scheduler_input_is_one_clear_error() -> None:
    with pytest.raises(InvalidArgumentError, match="solver must be one of mip, priority, got 'best'"):
        Scheduler(solver="best")  # type: ignore[arg-type]
    with pytest.raises(InvalidArgumentError, match="block id 'a' appears twice"):
        Scheduler().schedule([block("a"), block("a")], NIGHT)
    with pytest.raises(InvalidArgumentError, match=r"night start .* is not before its end"):
        Night(NIGHT.end, NIGHT.start, SITE)


def test_astroplan_places_blocks_back_to_back() -> None:
    # Two 1-h blocks exactly fill a 2-h window. astroplan's own bookkeeping loses the grid point at
    # the end of every block (float JD grid ~0.1 ms early), which would leave room for only one.
    window = ((hours(2.0), hours(4.0)),)
    blocks = [block(name, duration_s=3600.0, windows=window) for name in ("a", "b")]
    greedy = Scheduler(solver="priority", slew_overhead_s=0.0).schedule(blocks, NIGHT)
    assert [(s.start, s.end) for s in greedy.slots] == [(hours(2.0), hours(3.0)), (hours(3.0), hours(4.0))]
    assert greedy.objective == pytest.approx(2.0)


@pytest.mark.parametrize("solver", ["mip", "priority"])
def test_an_empty_archive_gives_an_empty_plan(solver: str) -> None:
    # The first plan of a new observatory, before any task is added (the replan loop crashed here).
    schedule = Scheduler(solver=solver).schedule([], NIGHT)  # type: ignore[arg-type]
    assert schedule.slots == ()
