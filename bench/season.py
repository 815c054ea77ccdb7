"""Benchmark: a season of random-weather nights on the one night engine, and whether it meets its goals.

Runs ``nightcrew sim --nights N --weather random`` (default 30 nights from 2026-11-10, frames
dropped after each night) and prints the season's table (per night and in total: shutter open in
the good-weather dark time, bad-weather onsets and the roof-close delay after them, exposures with
the roof closed, task outcomes, the first plan's objective against its bound, and where the
good-weather dark time went, by cause), then the goals:

- the roof closed within 60 s after every bad-weather onset that found it open;
- no exposure with the roof closed counted as science (``IMAGETYP = object``);
- the shutter open >= 90 % of the good-weather dark time, over the season.

``--configs DIR`` runs the observatory of DIR instead of the bundled one (a German-equatorial
mount: a copy of it with ``gem:`` in telescope.yaml, docs/mounts.md). ``--craft`` keeps each night's
frames until its craft numbers are taken (``bench/season_craft.py``; each night then runs as its own
process, ``--jobs`` at a time, so at most that many nights' frames are on disk) and adds the goals of
issue 27: no pier-limit collision, every meridian flip within 3 clock minutes from the last frame
before it to the first after it, the median science FWHM within 1.10 times the night's best focus
FWHM, and no science frame more than 0.5 °C off its cooling set point.

The nights are independent (each its own archive, seed ``--seed`` + its number, date ``--date`` +
its number), so ``--jobs`` child processes run consecutive runs of them side by side (default: one
per core) and the rows are put together: the same season as one run, in less wall time.

    .venv/bin/python bench/season.py [--nights 30] [--seed 1] [--date 2026-11-10] [--jobs N] [--out DIR]
        [--configs DIR] [--craft]
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from datetime import date, timedelta
from io import TextIOWrapper
from pathlib import Path

from nightcrew.night.build import bundled_observatory, observatory_site
from nightcrew.night.season import NIGHT_ROW
from nightcrew.report import (
    read_night,
    season_night,
    season_night_from,
    season_row,
    season_summary,
    season_table,
)

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # bench/season_craft.py
from bench.season_craft import CRAFT_JSON, NightCraft, craft_summary

#: The goals of the season (issue 15).
ROOF_CLOSE_GOAL_S, SHUTTER_GOAL = 60.0, 0.90
#: The goals of issue 27 (--craft).
FLIP_GOAL_S, FWHM_RATIO_GOAL = 180.0, 1.10


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nights", type=int, default=30, help="number of nights (default 30)")
    parser.add_argument("--seed", type=int, default=1, help="seed of the first night (default 1)")
    parser.add_argument("--date", type=date.fromisoformat, default=date(2026, 11, 10), help="first night")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="processes (default: cores)")
    parser.add_argument("--out", type=Path, default=None, help="output directory (default: a temporary one)")
    parser.add_argument("--configs", type=Path, default=None, help="observatory directory (default: bundled)")
    parser.add_argument("--craft", action="store_true", help="also the flip, focus and cooling numbers")
    args = parser.parse_args()
    load_before = os.getloadavg()[0]
    jobs = max(1, min(args.jobs, args.nights))
    crafts: list[NightCraft] = []
    with tempfile.TemporaryDirectory(prefix="nightcrew-season-") as scratch:
        out = args.out or Path(scratch) / "season"
        out.mkdir(parents=True, exist_ok=True)
        start = time.monotonic()
        if args.craft:
            failed = _nights_one_by_one(args, out, jobs, crafts)
        else:
            failed = _nights_in_parts(args, out, jobs)
        wall = time.monotonic() - start
        rows = [
            season_night_from(json.loads(path.read_text(encoding="utf-8")))
            for path in sorted(out.glob(f"part-*/night-*/{NIGHT_ROW}"), key=lambda p: p.parent.name)
        ]
    if failed or len(rows) != args.nights:
        print(f"{failed} runs failed; {len(rows)} of {args.nights} nights", file=sys.stderr)
        return 1
    season = season_summary(rows)
    where = args.configs or "the bundled observatory"
    print(f"{args.nights} nights from {args.date} on {where}, random weather, seed {args.seed}, {jobs} jobs")
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
    if args.craft:
        rows_met += _craft_goals(crafts)
    for goal, measured, ok in rows_met:
        print(f"{goal:<52}{measured:>14}  {'yes' if ok else 'NO'}")
    return 0


def _command(args: argparse.Namespace, out: Path, first: int, count: int) -> list[str]:
    """``nightcrew sim`` for nights ``first`` .. ``first + count - 1`` of the season into ``out``."""
    command = [sys.executable, "-m", "nightcrew", "sim", "--out", str(out)]
    command += ["--nights", str(count), "--weather", "random", "--seed", str(args.seed + first)]
    command += ["--date", (args.date + timedelta(days=first)).isoformat()]
    if args.configs is not None:
        command += ["--configs", str(args.configs)]
    return command


def _nights_in_parts(args: argparse.Namespace, out: Path, jobs: int) -> int:
    """Consecutive runs of nights side by side, one process each; how many failed."""
    children = []
    first = 0
    for job in range(jobs):
        count = args.nights // jobs + (1 if job < args.nights % jobs else 0)
        log = (out / f"part-{job}.log").open("w", encoding="utf-8")  # a pipe could fill and block
        command = _command(args, out / f"part-{job}", first, count)
        children.append((subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT), log))
        first += count
    return sum(_finished(child, log) for child, log in children)


def _nights_one_by_one(args: argparse.Namespace, out: Path, jobs: int, crafts: list[NightCraft]) -> int:
    """Every night its own process with its frames, ``jobs`` at a time; each night's craft numbers
    are taken as it ends and its frames removed. How many failed."""
    pending, failed = list(range(args.nights)), 0
    running: list[tuple[subprocess.Popen[bytes], TextIOWrapper, Path]] = []
    while pending or running:
        while pending and len(running) < jobs:
            number = pending.pop(0)
            part = out / f"part-{number}"
            log = (out / f"part-{number}.log").open("w", encoding="utf-8")
            craft = [sys.executable, str(Path(__file__).with_name("season_craft.py")), str(part)]
            # The numbers are taken in the night's own slot, so measuring overlaps the next nights.
            command = [
                "sh",
                "-c",
                f"{shlex.join([*_command(args, part, number, 1), '--frames'])} && {shlex.join(craft)}",
            ]
            running.append((subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT), log, part))
        time.sleep(1.0)
        for entry in [e for e in running if e[0].poll() is not None]:
            running.remove(entry)
            child, log, part = entry
            failed += _finished(child, log)
            if child.returncode == 0:
                crafts.append(_one_night(args, part, int(part.name.removeprefix("part-"))))
    return failed


def _one_night(args: argparse.Namespace, part: Path, number: int) -> NightCraft:
    """The season row (as ``--nights`` writes it) and the craft numbers of the single night run
    into ``part``; its frames removed."""
    site = observatory_site(args.configs or bundled_observatory())
    night = (args.date + timedelta(days=number)).isoformat()
    row = season_night(night, read_night(part), latitude=site.latitude, longitude=site.longitude)
    (part / f"night-{night}").mkdir(exist_ok=True)
    (part / f"night-{night}" / NIGHT_ROW).write_text(json.dumps(season_row(row), indent=1), encoding="utf-8")
    craft = NightCraft(**json.loads((part / CRAFT_JSON).read_text(encoding="utf-8")))
    shutil.rmtree(part / "frames", ignore_errors=True)
    shutil.rmtree(part / "thumbnails", ignore_errors=True)
    shown = vars(craft) | {"science_fwhm": len(craft.science_fwhm)}
    print(f"night {night}: shutter {100 * row.shutter_fraction:.1f} %, {shown}", file=sys.stderr, flush=True)
    return craft


def _finished(child: subprocess.Popen[bytes], log: TextIOWrapper) -> int:
    """1 if ``child`` failed (its log's tail shown), else 0."""
    child.wait()
    log.close()
    if child.returncode == 0:
        return 0
    print(Path(log.name).read_text(encoding="utf-8")[-3000:], file=sys.stderr)
    return 1


def _craft_goals(crafts: list[NightCraft]) -> list[tuple[str, str, bool]]:
    numbers = craft_summary(crafts)
    gap, ratio = numbers["flip_gap_max_s"], numbers["fwhm_ratio_median"]
    print(f"\ncraft: {json.dumps(numbers)}")
    return [
        ("0 pier-limit collisions", str(numbers["collisions"]), numbers["collisions"] == 0),
        (f"every flip <= {FLIP_GOAL_S:g} s, last frame to first ({numbers['flips']} flips)",
         "none" if gap is None else f"max {gap:.0f} s", gap is None or gap <= FLIP_GOAL_S),
        (f"median science FWHM <= {FWHM_RATIO_GOAL:g} x best focus FWHM",
         "-" if ratio is None else f"{ratio:.3f} x", ratio is not None and ratio <= FWHM_RATIO_GOAL),
        ("0 science frames > 0.5 °C off the set point",
         f"{numbers['off_set_point']} of {numbers['science_frames']}", numbers["off_set_point"] == 0),
    ]  # fmt: skip


if __name__ == "__main__":
    sys.exit(main())
