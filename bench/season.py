"""Benchmark: a season of random-weather nights on the one night engine, and whether it meets its goals.

Runs ``nightcrew sim --nights N --weather random`` (default 30 nights from 2026-11-10, frames
dropped after each night) and prints the season's table (per night and in total: shutter open in
the good-weather dark time, bad-weather onsets and the roof-close delay after them, exposures with
the roof closed, task outcomes, the first plan's objective against its bound, and where the
good-weather dark time went, by cause), then the goals:

- the roof closed within 60 s after every bad-weather onset that found it open;
- no exposure with the roof closed counted as science (``IMAGETYP = object``);
- the shutter open >= 90 % of the good-weather dark time, over the season.

The nights are independent (each its own archive, seed ``--seed`` + its number, date ``--date`` +
its number), so ``--jobs`` child processes run consecutive runs of them side by side (default: one
per core) and the rows are put together: the same season as one run, in less wall time.

    .venv/bin/python bench/season.py [--nights 30] [--seed 1] [--date 2026-11-10] [--jobs N] [--out DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from datetime import date, timedelta
from pathlib import Path

from nightcrew.night.season import NIGHT_ROW
from nightcrew.report import season_night_from, season_summary, season_table

#: The goals of the season (issue 15).
ROOF_CLOSE_GOAL_S, SHUTTER_GOAL = 60.0, 0.90


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nights", type=int, default=30, help="number of nights (default 30)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the first night (default 1)")
    parser.add_argument("--date", type=date.fromisoformat, default=date(2026, 11, 10), help="first night")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="processes (default: cores)")
    parser.add_argument("--out", type=Path, default=None, help="output directory (default: a temporary one)")
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    jobs = max(1, min(args.jobs, args.nights))
    with tempfile.TemporaryDirectory(prefix="nightcrew-season-") as scratch:
        out = args.out or Path(scratch) / "season"
        start = time.monotonic()
        children = []
        first = 0
        out.mkdir(parents=True, exist_ok=True)
        for job in range(jobs):
            count = args.nights // jobs + (1 if job < args.nights % jobs else 0)
            command = [sys.executable, "-m", "nightcrew", "sim", "--out", str(out / f"part-{job}")]
            command += ["--nights", str(count), "--weather", "random", "--seed", str(args.seed + first)]
            command += ["--date", (args.date + timedelta(days=first)).isoformat()]
            log = (out / f"part-{job}.log").open("w", encoding="utf-8")  # a pipe could fill and block
            children.append((subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT), log))
            first += count
        failed = 0
        for child, log in children:
            child.wait()
            log.close()
            if child.returncode != 0:
                failed += 1
                print(Path(log.name).read_text(encoding="utf-8")[-3000:], file=sys.stderr)
        wall = time.monotonic() - start
        rows = [
            season_night_from(json.loads(path.read_text(encoding="utf-8")))
            for path in sorted(out.glob(f"part-*/night-*/{NIGHT_ROW}"), key=lambda p: p.parent.name)
        ]
    if failed or len(rows) != args.nights:
        print(f"{failed} of {jobs} runs failed; {len(rows)} of {args.nights} nights", file=sys.stderr)
        return 1
    season = season_summary(rows)
    print(f"{args.nights} nights from {args.date}, random weather, seed {args.seed}, {jobs} processes")
    print(f"wall {wall:.0f} s ({jobs * wall / max(1, args.nights):.0f} s a night and process); "
          f"load average {load_before:.1f} before, {os.getloadavg()[0]:.1f} after\n")  # fmt: skip
    print(season_table(rows))
    delay_ok = season["roof_close_delay_max_s"] <= ROOF_CLOSE_GOAL_S
    science_ok = season["science_frames_while_closed"] == 0
    shutter_ok = season["shutter_fraction"] >= SHUTTER_GOAL
    print(f"{'goal':<52}{'measured':>14}  met")
    rows_met = [
        (f"roof closed <= {ROOF_CLOSE_GOAL_S:g} s after every bad-weather onset",
         f"max {season['roof_close_delay_max_s']:.1f} s", delay_ok),
        ("0 exposures with the roof closed counted as science",
         str(season["science_frames_while_closed"]), science_ok),
        (f"shutter >= {100 * SHUTTER_GOAL:g} % of good-weather dark time",
         f"{100 * season['shutter_fraction']:.1f} %", shutter_ok),
    ]  # fmt: skip
    for goal, measured, ok in rows_met:
        print(f"{goal:<52}{measured:>14}  {'yes' if ok else 'NO'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
