"""The craft numbers of a simulated night (issue 27), for ``bench/season.py --craft``.

From a night's directory (its frames and events.jsonl) before its frames go: pier-limit collisions
(the simulated mount's ERROR lines), each meridian flip's gap (a flip: two consecutive science
frames of one task on different sides of the pier) from the end of the last science frame before it
to the start of the first after it, the FWHM of every science frame against the night's best-focus
FWHM (of the focus-series frame nearest each focus found; both measured alike, by
:func:`~nightcrew.images.quality.measure_frame_quality`), and the science frames more than the
cooling margin off their set point (CCD-TEMP against SET-TEMP).
"""

from __future__ import annotations

import itertools
import json
import math
import sys
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path
from statistics import median

from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.errors import NightcrewError
from nightcrew.images import Image
from nightcrew.images.quality import measure_frame_quality

__all__ = ["CRAFT_JSON", "NightCraft", "craft_summary", "night_craft"]

#: A science frame further than this (°C) off its set point counts as off (issue 27).
COOLING_MARGIN = 0.5
#: Where :func:`main` writes a night's numbers.
CRAFT_JSON = "craft.json"
_COLLISION = "pier limit passed"


@dataclass(frozen=True)
class NightCraft:
    """One night's craft numbers (JSON-ready through ``vars``)."""

    collisions: int
    flip_gaps_s: list[float]
    science_fwhm: list[float]
    best_focus_fwhm: float | None
    science_frames: int
    off_set_point: int


@dataclass(frozen=True)
class _Frame:
    start: float
    end: float
    kind: str
    path: Path
    task: str | None
    side: str | None
    focus: float | None


def night_craft(night: Path) -> NightCraft:
    """The craft numbers of the night recorded in directory ``night`` (frames still there)."""
    found, collisions = _records(night / "events.jsonl")
    frames = sorted(_frames(night / "frames"), key=lambda f: f.start)
    science = [f for f in frames if f.kind == "object"]
    # A flip: two consecutive science frames of one task on different sides of the pier.
    gaps = [
        round(after.start - before.end, 1)
        for before, after in itertools.pairwise(science)
        if before.task == after.task and before.side != after.side
    ]
    focus = [f for f in frames if f.kind == "focus" and f.focus is not None]
    best = []
    for when, position in found:  # the series' frame nearest the focus it found
        series = [f for f in focus if f.end <= when]
        if series:
            nearest = min(series, key=lambda f: abs((f.focus or 0.0) - position))
            best.append(_fwhm(nearest.path))
    fwhm = [_fwhm(f.path) for f in science]
    off = sum(1 for f in science if not _at_set_point(f.path))
    finite = [v for v in best if math.isfinite(v)]
    return NightCraft(
        collisions=collisions,
        flip_gaps_s=gaps,
        science_fwhm=[round(v, 3) for v in fwhm if math.isfinite(v)],
        best_focus_fwhm=min(finite) if finite else None,
        science_frames=len(science),
        off_set_point=off,
    )


def _records(events: Path) -> tuple[list[tuple[float, float]], int]:
    """(clock time, focus) of every focus found, and the number of pier-limit collisions logged
    (an ERROR: recorded however quiet the night's log)."""
    found, collisions = [], 0
    for line in events.read_text(encoding="utf-8").splitlines():
        record = json.loads(line)
        if record.get("kind") == "FocusFoundEvent":
            found.append((float(record["t"]), float(record["data"]["focus"])))
        elif record.get("kind") == "LogEvent" and _COLLISION in str(record["data"].get("message", "")):
            collisions += 1
    return found, collisions


def _frames(folder: Path) -> list[_Frame]:
    frames = []
    for path in folder.glob("*.fits"):
        header = fits.getheader(path)
        start = _timestamp(str(header["DATE-OBS"]))
        end = start + float(header["EXPTIME"])
        task, side, focus = header.get("TASK-ID"), header.get("PIERSIDE"), header.get("FOCUS")
        focus = float(focus) - float(header.get("FOCOFFS", 0.0)) if isinstance(focus, int | float) else None
        frames.append(_Frame(start, end, str(header["IMAGETYP"]), path, task, side, focus))
    return frames


def _timestamp(iso: str) -> float:
    moment = datetime.fromisoformat(iso)
    return (moment if moment.tzinfo else moment.replace(tzinfo=UTC)).timestamp()


def _fwhm(path: Path) -> float:
    try:
        return measure_frame_quality(Image.from_bytes(path.read_bytes())).fwhm
    except NightcrewError:
        return math.nan


def _at_set_point(path: Path) -> bool:
    header = fits.getheader(path)
    temperature, set_point = header.get("CCD-TEMP"), header.get("SET-TEMP")
    if not isinstance(temperature, int | float) or not isinstance(set_point, int | float):
        return False  # a science frame without a cooled chip is off its set point
    return abs(float(temperature) - float(set_point)) <= COOLING_MARGIN


def craft_summary(nights: list[NightCraft]) -> dict[str, float | int | None]:
    """Totals of the season: collisions, flips and their longest gap, median FWHM ratio, frames off."""
    ratios = [fwhm / n.best_focus_fwhm for n in nights if n.best_focus_fwhm for fwhm in n.science_fwhm]
    gaps = [g for n in nights for g in n.flip_gaps_s]
    return {
        "collisions": sum(n.collisions for n in nights),
        "flips": len(gaps),
        "flip_gap_max_s": max(gaps) if gaps else None,
        "flip_gap_median_s": median(gaps) if gaps else None,
        "fwhm_ratio_median": round(median(ratios), 3) if ratios else None,
        "science_frames": sum(n.science_frames for n in nights),
        "off_set_point": sum(n.off_set_point for n in nights),
    }


def main() -> int:
    """``season_craft.py NIGHT``: the craft numbers of directory NIGHT into NIGHT/craft.json
    (bench/season.py runs it right after each night, in the night's process slot, and removes the
    frames once it has the night's row too)."""
    night = Path(sys.argv[1])
    (night / CRAFT_JSON).write_text(json.dumps(vars(night_craft(night))), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
