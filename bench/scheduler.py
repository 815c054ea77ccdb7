"""Benchmark of the MIP scheduler against astroplan's PriorityScheduler on synthetic nights.

Run: ``.venv/bin/python bench/scheduler.py [--sizes 50 200 500] [--seeds 1 2 3] [--step 300]
[--time-limit 10]``. Prints one table per request count, one row per seed: the MIP's objective (sum
of priority x observed hours), its proven bound on the grid, objective / bound, astroplan's objective
on the very same grid problem (same visibility, occupancies and weights), MIP / astroplan, bound /
astroplan (what no solver on this grid can beat), and ``cont. UB``: an upper bound for any schedule
of the same blocks in continuous time with free slews
(:func:`~nightcrew.robotic.scheduler.problem.density_bound`, on 60-s visibility), and the wall times.
Targets: >= 99 % of the bound within 10 s at 500 requests, and >= 1.15 x astroplan's objective.
"""

from __future__ import annotations

import argparse
import time
from datetime import UTC, datetime

from nightcrew.robotic.scheduler import Night, SchedulableBlock, Scheduler
from nightcrew.robotic.scheduler.problem import density_bound
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks
from nightcrew.site import Site

#: A long winter night at a mid-northern site (Sun below -12° from about 17:00 to 06:00 UTC).
SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
NIGHT = Night(datetime(2024, 1, 15, 17, 0, tzinfo=UTC), datetime(2024, 1, 16, 6, 0, tzinfo=UTC), SITE)
HEADER = (
    f"{'seed':>4} {'vars':>6} {'MIP obj':>8} {'bound':>8} {'obj/bnd':>7} {'astro':>8} {'MIP/ast':>7} "
    f"{'bnd/ast':>7} {'cont.UB':>8} {'UB/ast':>6} {'MIP s':>6} {'astro s':>7} {'MIP status':>13}"
)


def continuous_bound(blocks: list[SchedulableBlock]) -> float:
    """The density bound on 60-s visibility (no slew pad: slews cost >= 0 s)."""
    return density_bound(Scheduler(step_s=60.0, slew_overhead_s=0.0).problem(blocks, NIGHT))


def run(count: int, seed: int, step: float, time_limit: float) -> str:
    blocks = synthetic_blocks(NIGHT, count, seed=seed)
    mip = Scheduler(solver="mip", step_s=step, time_limit_s=time_limit)
    problem = mip.problem(blocks, NIGHT)
    began = time.perf_counter()
    optimal = mip.solve(problem)
    mip_s = time.perf_counter() - began
    began = time.perf_counter()
    greedy = Scheduler(solver="priority", step_s=step).solve(problem)
    greedy_s = time.perf_counter() - began
    bound = optimal.bound if optimal.bound is not None else float("nan")
    upper = continuous_bound(blocks)
    return (
        f"{seed:>4} {int(problem.can_start.sum()):>6} {optimal.objective:>8.2f} {bound:>8.2f} "
        f"{100 * optimal.objective / bound:>6.2f}% {greedy.objective:>8.2f} "
        f"{optimal.objective / greedy.objective:>6.3f}x {bound / greedy.objective:>6.3f}x {upper:>8.2f} "
        f"{upper / greedy.objective:>5.3f}x {mip_s:>6.2f} {greedy_s:>7.2f} {optimal.status:>13}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[50, 200, 500])
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    parser.add_argument("--step", type=float, default=300.0, help="slice length in seconds, both solvers")
    parser.add_argument("--time-limit", type=float, default=10.0)
    args = parser.parse_args()
    night = f"{NIGHT.start:%Y-%m-%d %H:%M} - {NIGHT.end:%H:%M} UTC at {SITE.name}"
    print(f"night {night}, {args.step:g}-s slices for both solvers")
    for count in args.sizes:
        print(f"\n{count} requests")
        print(HEADER)
        for seed in args.seeds:
            print(run(count, seed, args.step, args.time_limit), flush=True)


if __name__ == "__main__":
    main()
