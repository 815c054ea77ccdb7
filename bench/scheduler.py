"""Benchmark of the MIP scheduler against astroplan's PriorityScheduler, judged by one evaluator.

Run: ``.venv/bin/python bench/scheduler.py [--seeds 1 2] [--step 300] [--loaded]``. Three families
of requests from :mod:`nightcrew.robotic.scheduler.synthetic` (seeded): ``queue`` (500 requests, a
fifth with 1-4 h windows), ``narrow`` (160 time-critical requests, windows of 15-45 min opening at
any second), ``cadence`` (250 visits of monitoring series: every 40-90 min within +-10 min). For
each set:

- ``mip``: the scheduler as shipped (refined grid, the slew model below: transitions exact);
- ``flat``: the same MIP with today's flat 100-s slew pad and no refinement (the old plan);
- ``astroplan``: astroplan's PriorityScheduler on the plain grid with the flat pad.

One evaluator judges every plan with astropy alone: each placed block sampled every minute from its
start to its end (target altitude in astropy's AltAz, Sun and topocentric Moon from ``get_body``),
its window, overlaps and (all plans) the slew model's transition before it. Columns: objective
(sum of priority x observed hours), ``bound`` (the solver's proven upper bound: the time-indexed
model on the refined grid with each block's least transition, so valid for every plan that pays
the real transitions and starts on the grid), value / bound, CPU seconds of the solve
(``time.process_time``), ``lost``: time-critical (windowed) requests feasible on their own but not
placed, of which ``free`` could have been added to the plan without moving anything, ``viol``:
constraint, window, overlap or transition violations found by the evaluator. With ``--loaded``
two ``yes`` processes keep both cores busy and the MIP is solved again: ``same`` says whether the
plan is identical.
"""

from __future__ import annotations

import argparse
import itertools
import subprocess
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime

import numpy as np

from nightcrew.astro import airmass
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.scheduler import Night, SchedulableBlock, Schedule, Scheduler
from nightcrew.robotic.scheduler.sequence import pointing_of
from nightcrew.robotic.scheduler.slew import SlewModel
from nightcrew.robotic.scheduler.synthetic import cadence_blocks, narrow_window_blocks, synthetic_blocks
from nightcrew.site import Site

#: A long winter night at a mid-northern site (Sun below -12° from about 17:00 to 06:00 UTC).
SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
NIGHT = Night(datetime(2024, 1, 15, 17, 0, tzinfo=UTC), datetime(2024, 1, 16, 6, 0, tzinfo=UTC), SITE)
#: A 0.4-m telescope on an equatorial mount in a dome.
MOUNT = SlewModel.from_config(
    {
        "axis_rates": [3.0, 3.0],
        "acceleration": 1.0,
        "settle_time": 5.0,
        "dome_rate": 4.0,
        "filter_change_s": 10.0,
    }
)
FAMILIES: dict[str, Callable[[int], list[SchedulableBlock]]] = {
    "queue": lambda seed: synthetic_blocks(NIGHT, 500, seed=seed),
    "narrow": lambda seed: narrow_window_blocks(NIGHT, 160, seed=seed),
    "cadence": lambda seed: cadence_blocks(NIGHT, 250, seed=seed),
}
HEADER = (
    f"{'family':>8} {'seed':>4} {'plan':>9} {'placed':>6} {'value':>8} {'bound':>8} {'val/bnd':>7} "
    f"{'cpu s':>6} {'lost':>4} {'free':>4} {'viol':>4} {'same':>5}"
)


@dataclass
class Judgement:
    violations: int
    lost: int
    free: int


def evaluate(
    blocks: Sequence[SchedulableBlock], slots: Sequence[PlannedSlot], scheduler: Scheduler
) -> Judgement:
    """Every constraint of every placed block each minute, with astropy; time-critical requests lost."""
    import astropy.units as u  # type: ignore[import-untyped]
    from astropy.coordinates import AltAz, EarthLocation, SkyCoord, get_body  # type: ignore[import-untyped]
    from astropy.time import Time  # type: ignore[import-untyped]
    from astropy.utils import iers  # type: ignore[import-untyped]

    by_id = {b.id: b for b in blocks}
    location = EarthLocation.from_geodetic(
        SITE.longitude * u.deg, SITE.latitude * u.deg, SITE.elevation * u.m
    )
    rows: list[int] = []
    times: list[float] = []
    for index, slot in enumerate(slots):
        begin, end = slot.start.timestamp(), slot.end.timestamp()
        samples = np.append(np.arange(begin, end, 60.0), end)
        rows.extend([index] * len(samples))
        times.extend(samples)
    violations = 0
    if slots:
        row, unix = np.array(rows), np.array(times)
        ra = np.array([by_id[slots[r].task_id].target.ra for r in row])
        dec = np.array([by_id[slots[r].task_id].target.dec for r in row])
        with (
            iers.conf.set_temp("auto_download", False),
            iers.conf.set_temp("iers_degraded_accuracy", "ignore"),
        ):
            t = Time(unix, format="unix")
            frame = AltAz(obstime=t, location=location)
            altitude = SkyCoord(ra * u.deg, dec * u.deg).transform_to(frame).alt.deg
            sun = get_body("sun", t, location).transform_to(frame).alt.deg
            moon = get_body("moon", t, location)  # seen from the site: its direction, as plain (ra, dec)
            moon_distance = SkyCoord(ra * u.deg, dec * u.deg).separation(SkyCoord(moon.ra, moon.dec)).deg
        bad = np.zeros(len(row), dtype=bool)
        for k, r in enumerate(row):
            c = by_id[slots[r].task_id].constraints
            mass = airmass(float(altitude[k]))
            bad[k] = (
                ((mass is None or mass > c.max_airmass) and np.isfinite(c.max_airmass))
                or sun[k] > c.max_sun_altitude + 1e-6
                or moon_distance[k] < c.min_moon_distance - 1e-6
            )
        violations += len(set(row[bad]))
    for slot in slots:
        windows = by_id[slot.task_id].windows
        if windows and not any(a <= slot.start and slot.end <= b for a, b in windows):
            violations += 1
    for before, after in itertools.pairwise(slots):
        needed = MOUNT.transition_s(
            SITE,
            pointing_of(by_id[before.task_id]),
            pointing_of(by_id[after.task_id]),
            after.start.timestamp(),
        )
        block = by_id[after.task_id]
        if (
            before.end > after.start
            or (after.end - after.start).total_seconds() < needed + block.setup_s + block.duration_s - 1e-3
        ):
            violations += 1
    lost, free = _lost(blocks, slots, scheduler)
    return Judgement(violations, lost, free)


def _lost(
    blocks: Sequence[SchedulableBlock], slots: Sequence[PlannedSlot], scheduler: Scheduler
) -> tuple[int, int]:
    """Windowed requests that fit alone (the refined model, with their least transition) but are not
    placed; and of those, how many fit a gap of the plan, its slew in the window too, with the
    transitions on both sides and nothing else moved."""
    problem = Scheduler(step_s=scheduler.step_s, slew=MOUNT).problem(blocks, NIGHT)
    placed = {s.task_id for s in slots}
    by_id = {b.id: b for b in blocks}
    edges = problem.grid.edges
    visible_before = np.zeros((len(problem.blocks), problem.grid.n_slices + 1), dtype=np.int64)
    np.cumsum(problem.visible, axis=1, out=visible_before[:, 1:])
    lost = free = 0
    for row, block in enumerate(problem.blocks):
        if not block.windows or block.id in placed or not problem.can_start[row].any():
            continue
        lost += 1
        for index in range(len(slots) + 1):
            before = slots[index - 1] if index > 0 else None
            after = slots[index] if index < len(slots) else None
            gap_start = before.end.timestamp() if before else NIGHT.start.timestamp()
            gap_end = after.start.timestamp() if after else NIGHT.end.timestamp()
            starts = edges[np.flatnonzero(problem.can_start[row])]
            if _fits_gap(block, row, before, after, gap_start, gap_end, starts, by_id, edges, visible_before):
                free += 1
                break
    return lost, free


def _fits_gap(
    block: SchedulableBlock,
    row: int,
    before: PlannedSlot | None,
    after: PlannedSlot | None,
    gap_start: float,
    gap_end: float,
    starts: np.ndarray,
    by_id: dict[str, SchedulableBlock],
    edges: np.ndarray,
    visible_before: np.ndarray,
) -> bool:
    for start in (gap_start, *starts[(starts > gap_start) & (starts < gap_end)]):
        into = (
            MOUNT.transition_s(SITE, pointing_of(by_id[before.task_id]), pointing_of(block), start)
            if before
            else 0
        )
        end = start + into + block.setup_s + block.duration_s
        out = (
            MOUNT.transition_s(SITE, pointing_of(block), pointing_of(by_id[after.task_id]), end)
            if after
            else 0
        )
        first = max(0, int(np.searchsorted(edges, start, side="right")) - 1)
        last = int(np.searchsorted(edges, end, side="left"))
        seen = visible_before[row, min(last, len(edges) - 1)] - visible_before[row, first] == last - first
        inside = any(a.timestamp() <= start and end <= b.timestamp() for a, b in block.windows)
        if seen and inside and end + out <= gap_end:
            return True
    return False


def _solve(scheduler: Scheduler, blocks: list[SchedulableBlock]) -> tuple[Schedule, float]:
    began = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        schedule = scheduler.schedule(blocks, NIGHT)
    return schedule, time.process_time() - began


def run(family: str, seed: int, step: float, loaded: bool) -> list[str]:
    blocks = FAMILIES[family](seed)
    plans = {
        "mip": Scheduler(step_s=step, slew=MOUNT),
        "flat": Scheduler(step_s=step, slew_overhead_s=100.0),
        "astroplan": Scheduler(solver="priority", step_s=step, slew_overhead_s=100.0),
    }
    lines = []
    for name, scheduler in plans.items():
        schedule, cpu = _solve(scheduler, blocks)
        judged = evaluate(blocks, schedule.slots, scheduler)
        same = ""
        if loaded and name == "mip":
            same = "yes" if _solve_loaded(scheduler, blocks).slots == schedule.slots else "NO"
        bound = schedule.bound if schedule.bound is not None else float("nan")
        ratio = 100 * schedule.objective / bound if bound == bound and bound > 0 else float("nan")
        lines.append(
            f"{family:>8} {seed:>4} {name:>9} {len(schedule.slots):>6} {schedule.objective:>8.2f} "
            f"{bound:>8.2f} "
            f"{ratio:>6.2f}% {cpu:>6.2f} {judged.lost:>4} {judged.free:>4} {judged.violations:>4} {same:>5}"
        )
    return lines


def _solve_loaded(scheduler: Scheduler, blocks: list[SchedulableBlock]) -> Schedule:
    """The same solve with both cores kept busy by ``yes`` (stopped by their own process ids)."""
    hogs = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(2)]
    try:
        return _solve(scheduler, blocks)[0]
    finally:
        for hog in hogs:
            hog.kill()
            hog.wait()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--families", nargs="+", default=list(FAMILIES), choices=list(FAMILIES))
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--step", type=float, default=300.0, help="coarse slice length in seconds")
    parser.add_argument("--loaded", action="store_true", help="solve the MIP again with both cores busy")
    args = parser.parse_args()
    print(
        f"night {NIGHT.start:%Y-%m-%d %H:%M} - {NIGHT.end:%H:%M} UTC at {SITE.name}, "
        f"{args.step:g}-s coarse slices"
    )
    print(HEADER)
    for family in args.families:
        for seed in args.seeds:
            for line in run(family, seed, args.step, args.loaded):
                print(line, flush=True)


if __name__ == "__main__":
    main()
