"""Benchmark: a whole robotic night of ``nightcrew sim``: wall time, peak memory, and its numbers.

Runs ``nightcrew sim`` in a child process (default: 10 clock hours from dusk with the
``interruption`` weather at the default speed, every frame rendered and written), then prints one
table: wall seconds, peak RSS of the child, frames, and the night's numbers as the report computes
them (shutter open in the good-weather dark time, exposures while the roof was closed, roof-close
delay after bad weather, task outcomes, time from task start to first science frame), then where
the good-weather dark time went (:func:`nightcrew.report.time_budget`, as in the report: exposing,
read-out, slews, focus runs, idle in and between tasks).

    .venv/bin/python bench/night.py [--hours 10] [--weather interruption] [--seed N] [--speed S] [--out DIR]
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

from nightcrew.report import acquisitions, night_numbers, night_site, read_night, time_budget

#: Targets of the issue: a 10-hour night within this wall time and peak memory.
WALL_TARGET_S, RSS_TARGET_MB = 180.0, 1536.0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--hours", type=float, default=10.0, help="clock hours from dusk (default 10)")
    parser.add_argument("--weather", default="interruption")
    parser.add_argument("--seed", type=int, default=None, help="seed of the night (default: the configs')")
    parser.add_argument("--speed", type=float, default=None, help="clock speed (default: nightcrew sim's)")
    parser.add_argument("--out", type=Path, default=None, help="output directory (default: a temporary one)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="nightcrew-night-") as scratch:
        out = args.out or Path(scratch)
        command = [sys.executable, "-m", "nightcrew", "sim", "--out", str(out), "--hours", str(args.hours)]
        command += ["--weather", args.weather] + (["--speed", str(args.speed)] if args.speed else [])
        command += ["--seed", str(args.seed)] if args.seed is not None else []
        start = time.monotonic()
        result = subprocess.run(command, capture_output=True, text=True, check=False)
        wall = time.monotonic() - start
        if result.returncode != 0:
            print(result.stdout, result.stderr, sep="\n", file=sys.stderr)
            return result.returncode
        rss_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
        night = read_night(out)
        latitude, longitude = night_site(night)
        numbers = night_numbers(night, latitude=latitude, longitude=longitude)
        spent = time_budget(night, latitude=latitude, longitude=longitude)
        to_science = sorted(s for a in acquisitions(night) if (s := a.seconds) is not None)
    outcomes = Counter(t.outcome for t in numbers.tasks)
    rows = [
        ("clock hours", f"{args.hours:g}", ""),
        ("wall time", f"{wall:.1f} s", f"target <= {WALL_TARGET_S:g} s"),
        ("peak RSS", f"{rss_mb:.0f} MB", f"target <= {RSS_TARGET_MB:g} MB"),
        (
            "frames written",
            str(len(night.frames)),
            ", ".join(f"{n} {k}" for k, n in Counter(f.image_type for f in night.frames).items()),
        ),
        ("good-weather dark time", f"{numbers.good_dark_s / 3600:.2f} h", "Sun < -12 deg, weather not bad"),
        ("roof open in it", f"{100 * numbers.roof_open_fraction:.1f} %", "target >= 90 %"),
        ("camera shutter open in it", f"{100 * numbers.shutter_open_fraction:.1f} %", "exposing"),
        ("science exposures, roof closed", str(numbers.science_frames_while_closed), "target 0"),
        ("light exposures, roof closed", str(numbers.light_frames_while_closed), ""),
        (
            "roof closed after bad weather",
            ", ".join(f"{d:.0f} s" for d in numbers.roof_close_delays_s) or "-",
            "target <= 60 s",
        ),
        (
            "task runs",
            ", ".join(f"{n} {k}" for k, n in sorted(outcomes.items())),
            f"{len(numbers.tasks_without_reason)} without done/reason",
        ),
        (
            "task start to 1st science",
            f"{statistics.median(to_science):.0f} s" if to_science else "-",
            f"median of {len(to_science)}, {to_science[0]:.0f}-{to_science[-1]:.0f} s" if to_science else "",
        ),
    ]
    width = max(len(r[0]) for r in rows)
    print(f"{'':{width}}  {'value':>12}  note")
    for name, value, note in rows:
        print(f"{name:{width}}  {value:>12}  {note}")
    print()
    whole = sum(spent.values()) or 1.0
    print(f"{'good-weather dark time':28}  {whole / 60:7.1f} min")
    for label, seconds in spent.items():
        print(f"  {label:26}  {seconds / 60:7.1f} min  {100 * seconds / whole:5.1f} %")
    return 0


if __name__ == "__main__":
    sys.exit(main())
