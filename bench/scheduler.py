"""Benchmark of the MIP scheduler against astroplan's PriorityScheduler on synthetic nights.

Run: ``.venv/bin/python bench/scheduler.py [--sizes 50 200 500] [--seed 1] [--time-limit 10]``.
Prints one table: per request count, the MIP's objective (sum of priority x observed hours), its
proven bound, objective / bound, astroplan's objective on the very same problem (same visibility,
occupancies and weights), their ratio and the wall time of each. Targets: >= 99 % of the bound
within 10 s at 500 requests, and >= 1.15 x astroplan's objective.
"""

from __future__ import annotations

import argparse
import time
from datetime import UTC, datetime

from nightcrew.robotic.scheduler import Night, Scheduler
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks
from nightcrew.site import Site

#: A long winter night at a mid-northern site (Sun below -12° from about 17:00 to 06:00 UTC).
SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
NIGHT = Night(datetime(2024, 1, 15, 17, 0, tzinfo=UTC), datetime(2024, 1, 16, 6, 0, tzinfo=UTC), SITE)
HEADER = (
    f"{'requests':>8} {'vars':>6} {'MIP obj':>9} {'MIP bound':>9} {'obj/bound':>9} {'astroplan':>9} "
    f"{'MIP/astro':>9} {'MIP s':>6} {'astro s':>7} {'MIP status':>13}"
)


def run(count: int, seed: int, time_limit: float) -> str:
    blocks = synthetic_blocks(NIGHT, count, seed=seed)
    mip = Scheduler(solver="mip", time_limit_s=time_limit)
    problem = mip.problem(blocks, NIGHT)
    began = time.perf_counter()
    optimal = mip.solve(problem)
    mip_s = time.perf_counter() - began
    began = time.perf_counter()
    greedy = Scheduler(solver="priority").solve(problem)
    greedy_s = time.perf_counter() - began
    bound = optimal.bound if optimal.bound is not None else float("nan")
    return (
        f"{count:>8} {int(problem.can_start.sum()):>6} {optimal.objective:>9.2f} {bound:>9.2f} "
        f"{100 * optimal.objective / bound:>8.2f}% {greedy.objective:>9.2f} "
        f"{optimal.objective / greedy.objective:>8.3f}x {mip_s:>6.2f} {greedy_s:>7.2f} {optimal.status:>13}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[50, 200, 500])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--time-limit", type=float, default=10.0)
    args = parser.parse_args()
    print(f"night {NIGHT.start:%Y-%m-%d %H:%M} - {NIGHT.end:%H:%M} UTC at {SITE.name}, seed {args.seed}")
    print(HEADER)
    for count in args.sizes:
        print(run(count, args.seed, args.time_limit), flush=True)


if __name__ == "__main__":
    main()
