"""Benchmark: a season of random-weather nights on the one night engine, and whether it meets its goals.

Runs ``nightcrew sim --nights N --weather random`` (default 30 nights from 2026-11-10, frames
dropped after each night) in a child process and prints the season's table (per night and in
total: shutter open in the good-weather dark time, bad-weather onsets and the roof-close delay
after them, exposures with the roof closed, task outcomes, the first plan's objective against
its bound), then the goals:

- the roof closed within 60 s after every bad-weather onset that found it open;
- no exposure with the roof closed counted as science (``IMAGETYP = object``);
- the shutter open >= 90 % of the good-weather dark time, over the season.

    .venv/bin/python bench/season.py [--nights 30] [--seed 1] [--date 2026-11-10] [--out DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: The goals of the season (issue 15).
ROOF_CLOSE_GOAL_S, SHUTTER_GOAL = 60.0, 0.90


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nights", type=int, default=30, help="number of nights (default 30)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the first night (default 1)")
    parser.add_argument("--date", default="2026-11-10", help="first night (default 2026-11-10)")
    parser.add_argument("--out", type=Path, default=None, help="output directory (default: a temporary one)")
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="nightcrew-season-") as scratch:
        out = args.out or Path(scratch) / "season"
        command = [sys.executable, "-m", "nightcrew", "sim", "--out", str(out), "--nights", str(args.nights)]
        command += ["--weather", "random", "--seed", str(args.seed), "--date", args.date]
        start = time.monotonic()
        result = subprocess.run(command, capture_output=True, text=True, check=False)
        wall = time.monotonic() - start
        if result.returncode != 0:
            print(result.stdout[-3000:], result.stderr[-3000:], sep="\n", file=sys.stderr)
            return result.returncode
        table = (out / "season.md").read_text(encoding="utf-8")
        season = json.loads((out / "season.json").read_text(encoding="utf-8"))
    print(f"{args.nights} nights from {args.date}, random weather, seed {args.seed}")
    print(f"wall {wall:.0f} s ({wall / max(1, args.nights):.0f} s a night); load average {load_before:.1f}\n")
    print(table)
    delay_ok = season["roof_close_delay_max_s"] <= ROOF_CLOSE_GOAL_S
    science_ok = season["science_frames_while_closed"] == 0
    shutter_ok = season["shutter_fraction"] >= SHUTTER_GOAL
    print(f"{'goal':<52}{'measured':>14}  met")
    rows = [
        (f"roof closed <= {ROOF_CLOSE_GOAL_S:g} s after every bad-weather onset",
         f"max {season['roof_close_delay_max_s']:.1f} s", delay_ok),
        ("0 exposures with the roof closed counted as science",
         str(season["science_frames_while_closed"]), science_ok),
        (f"shutter >= {100 * SHUTTER_GOAL:g} % of good-weather dark time",
         f"{100 * season['shutter_fraction']:.1f} %", shutter_ok),
    ]  # fmt: skip
    for goal, measured, ok in rows:
        print(f"{goal:<52}{measured:>14}  {'yes' if ok else 'NO'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
