"""Benchmark: a whole robotic night of ``nightcrew sim``: wall time, peak memory, and its numbers.

Runs ``nightcrew sim`` in a child process (default: 10 clock hours from dusk with the
``interruption`` weather on the virtual clock, every frame rendered and written), then once more
with a ``yes > /dev/null`` load per core beside it, and prints one table: wall and CPU seconds,
peak RSS of the child, whether the busy run gave the same night byte for byte (events.jsonl and
every frame), frames, and the night's numbers as the report computes them (shutter open in the
good-weather dark time, exposures while the roof was closed, roof-close delay after bad weather,
task outcomes, time from task start to first science frame); then where the wall time went (the
loop's waits on thread jobs by function, the rest is the event loop's own Python), and where the
good-weather dark time went (:func:`nightcrew.report.time_budget`, as in the report: exposing,
read-out, slews, focus runs, idle in and between tasks). The machine's load average is printed
with it: the wall time depends on it, the night does not.

    .venv/bin/python bench/night.py [--hours 10] [--weather interruption] [--seed N] [--speed S]
                                    [--out DIR] [--once]
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from nightcrew.night.sim import WALL_TIME_FILE
from nightcrew.report import acquisitions, night_numbers, night_site, read_night, time_budget

#: Targets of the issue: a 10-hour night within this wall time and peak memory.
WALL_TARGET_S, RSS_TARGET_MB = 70.0, 1536.0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--hours", type=float, default=10.0, help="clock hours from dusk (default 10)")
    parser.add_argument("--weather", default="interruption")
    parser.add_argument("--seed", type=int, default=None, help="seed of the night (default: the configs')")
    parser.add_argument("--speed", type=float, default=None, help="clock speed (default: nightcrew sim's)")
    parser.add_argument("--out", type=Path, default=None, help="output directory (default: a temporary one)")
    parser.add_argument("--once", action="store_true", help="skip the second run with both cores busy")
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="nightcrew-night-") as scratch:
        out = args.out or Path(scratch) / "night"
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
        spent_wall = json.loads((out / WALL_TIME_FILE).read_text(encoding="utf-8"))
        busy = "not run (--once)"
        if not args.once:
            again = Path(scratch) / "busy" / "night"
            with both_cores_busy():
                began = time.monotonic()
                rerun = subprocess.run(
                    [*command[:5], str(again), *command[6:]], capture_output=True, text=True, check=False
                )
                busy_wall = time.monotonic() - began
            if rerun.returncode != 0:
                print(rerun.stdout, rerun.stderr, sep="\n", file=sys.stderr)
            same = rerun.returncode == 0 and fingerprint(out) == fingerprint(again)
            busy = f"{'identical' if same else 'DIFFERENT'} ({busy_wall:.0f} s wall)"
        night = read_night(out)
        latitude, longitude = night_site(night)
        numbers = night_numbers(night, latitude=latitude, longitude=longitude)
        spent = time_budget(night, latitude=latitude, longitude=longitude)
        to_science = sorted(s for a in acquisitions(night) if (s := a.seconds) is not None)
    outcomes = Counter(t.outcome for t in numbers.tasks)
    rows = [
        ("clock hours", f"{args.hours:g}", ""),
        ("wall time", f"{wall:.1f} s", f"target <= {WALL_TARGET_S:g} s; load average {load_before:.1f}"),
        ("CPU time of the night", f"{spent_wall['cpu_s']:.1f} s", "all threads of the child"),
        ("both cores busy", busy.split(" ")[0], busy.partition(" ")[2] + " events.jsonl + frames"),
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
    waited = spent_wall.get("waited_s", {})
    loop_own = wall - sum(waited.values())
    print(f"{'wall time':28}  {wall:7.1f} s")
    for label, seconds in [*waited.items(), ("event loop (Python, start-up)", loop_own)]:
        print(f"  {label[:40]:40}  {seconds:7.1f} s  {100 * seconds / wall:5.1f} %")
    print()
    whole = sum(spent.values()) or 1.0
    print(f"{'good-weather dark time':28}  {whole / 60:7.1f} min")
    for label, seconds in spent.items():
        print(f"  {label:26}  {seconds / 60:7.1f} min  {100 * seconds / whole:5.1f} %")
    return 0


@contextmanager
def both_cores_busy() -> Iterator[None]:
    """A ``yes > /dev/null`` per core while inside; stopped by their PIDs."""
    loads = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(os.cpu_count() or 2)]
    try:
        yield
    finally:
        for load in loads:
            load.kill()
            load.wait()


def fingerprint(out: Path) -> list[tuple[str, str]]:
    """Checksums of the night's record and frames."""
    files = [out / "events.jsonl", *sorted((out / "frames").glob("*.fits"))]
    return [(p.name, hashlib.sha256(p.read_bytes()).hexdigest()) for p in files]


if __name__ == "__main__":
    sys.exit(main())
