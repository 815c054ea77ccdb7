"""Benchmark: ``nightcrew reduce`` of a whole simulated night, and where its time went.

Run ``make sim`` first (a night's frames in ``sim-output/frames``), then
``.venv/bin/python bench/reduce.py [SIM_OUTPUT] [--workers N] [--index-dir DIR]``. The catalog
matcher and the plate-solving service started for the run (``nightcrew solver``, the second solver;
solve-field stays off) both use the index files of ``--index-dir``: by default the simulated sky's
that ``make sim`` built (``~/.cache/nightcrew/indexes/seed42-G16``). Prints the wall time against
the target (<= 120 s for ~220 frames on 2 cores), how many science frames were solved and by which
solver, and a table of seconds per stage (summed over the frames reduced at once, so it can exceed
the wall time).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import tempfile
import time
from collections import Counter
from pathlib import Path

from nightcrew.images.reduce import ReduceOptions, StageTimes, find_raw_frames, reduce_night
from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.sky_index import sky_index_dir
from nightcrew.testing.solver import running_solver

TARGET_WALL_S = 120.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("sim_output", nargs="?", type=Path, default=Path("sim-output"))
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--index-dir", type=Path, default=sky_index_dir(StarCatalog(seed=42, depth=16.0)))
    args = parser.parse_args()
    files = find_raw_frames(args.sim_output)
    times = StageTimes()
    index_dir: Path = args.index_dir
    with (
        running_solver(index_dir=index_dir) as url,
        tempfile.TemporaryDirectory(prefix="bench-reduce-") as out,
    ):
        options = ReduceOptions(
            index_dir=str(index_dir), solver_url=url, solve_field=False, workers=args.workers
        )
        started, cpu = time.perf_counter(), time.process_time()
        rows = asyncio.run(reduce_night(args.sim_output, Path(out), options=options, times=times))
        wall, cpu = time.perf_counter() - started, time.process_time() - cpu
    science = [r for r in rows if r.role == "object"]
    solved = [r for r in science if r.status == "reduced" and r.solver]
    by_solver = Counter(r.solver for r in solved)
    print(f"nightcrew reduce of {len(files)} files ({len(science)} science frames), {args.workers} workers")
    print(f"{'':24}{'measured':>12}{'target':>12}")
    print(f"{'wall time':24}{wall:>11.1f}s{'<= ' + format(TARGET_WALL_S, 'g') + ' s':>12}")
    print(f"{'CPU time (this process)':24}{cpu:>11.1f}s")
    print(f"{'science frames solved':24}{len(solved):>8}/{len(science):<3}{'all':>12}")
    print(f"{'  by solver':24}{', '.join(f'{k} {v}' for k, v in sorted(by_solver.items())):>12}")
    for row in science:
        if not row.solver:
            print(f"  unsolved: {row.file}: {row.status}: {row.message}")
    total = sum(times.seconds.values())
    print(f"\n{'stage':24}{'seconds':>12}{'share':>12}{'per frame':>12}")
    for stage, seconds in sorted(times.seconds.items(), key=lambda item: -item[1]):
        print(
            f"{stage:24}{seconds:>12.1f}{100 * seconds / total:>11.0f}%"
            f"{1000 * seconds / max(len(science), 1):>10.0f}ms"
        )
    print(
        f"{'masters, reading, rest':22}{max(0.0, wall * args.workers - total):>12.1f}  (wall x workers - sum)"
    )


if __name__ == "__main__":
    main()
