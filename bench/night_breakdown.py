"""Where a simulated night's good-weather dark time went, from its records (pure, for bench/night.py).

Every instant of the good-weather dark time (Sun below -12°, weather not bad) gets the first label
that applies, in this order:

* ``exposing <type>``: a light frame of that IMAGETYP (object, focus, acquisition, skyflat) exposes;
* ``readout``: the camera reads out (its ExposureStatusChangedEvents);
* ``slew``: the telescope slews, initialises or parks;
* ``roof not open``: the roof is closed or moving although the weather is good;
* ``focus run, between frames``: from the first to the last frame of a focus series;
* ``in a task, camera idle``: a task runs but the camera neither exposes nor reads out (frame
  writing and analysis, filter changes, acquisition solving, guiding start-up);
* ``no task running``: the mastermind runs nothing (nothing schedulable, waiting, polling).

    .venv/bin/python bench/night_breakdown.py OUT_DIR     # a night that ``nightcrew sim`` wrote
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from pathlib import Path

from nightcrew.report import Night, night_site, read_night
from nightcrew.report._data import Record, bad_weather_intervals, roof_open_intervals, task_runs
from nightcrew.report._metrics import dark_intervals, intersect, subtract, total

__all__ = ["breakdown", "main", "print_breakdown"]

Interval = tuple[float, float]


def breakdown(night: Night, *, latitude: float, longitude: float) -> dict[str, float]:
    """Clock seconds of the good-weather dark time per label (see the module doc); sums to it."""
    start, end = night.span
    good = subtract(
        dark_intervals(latitude, longitude, start, end, -12.0), bad_weather_intervals(night.records, end)
    )
    layers: list[tuple[str, list[Interval]]] = []
    for kind in sorted({f.image_type for f in night.frames if f.light}):
        frames = [(f.start, f.end) for f in night.frames if f.light and f.image_type == kind]
        layers.append((f"exposing {kind}", _union(frames)))
    layers.append(
        (
            "readout",
            _states(night.records, "camera", "ExposureStatusChangedEvent", "current", {"readout"}, end),
        )
    )
    moving = {"slewing", "initializing", "parking"}
    layers.append(
        ("slew", _states(night.records, "telescope", "MotionStatusChangedEvent", "status", moving, end))
    )
    layers.append(("roof not open", subtract([(start, end)], roof_open_intervals(night.records, end))))
    focus = [f for f in night.frames if f.image_type == "focus"]
    layers.append(("focus run, between frames", _series_spans([f.start for f in focus], gap=900.0)))
    runs = [(r.start, r.end if r.end is not None else end) for r in task_runs(night.records)]
    layers.append(("in a task, camera idle", _union(runs)))
    layers.append(("no task running", [(start, end)]))
    result: dict[str, float] = {}
    left = good
    for label, intervals in layers:
        taken = intersect(left, _union(intervals))
        result[label] = total(taken)
        left = subtract(left, taken)
    return result


def _states(
    records: Sequence[Record], sender: str, kind: str, key: str, states: set[str], end: float
) -> list[Interval]:
    """When ``sender``'s ``kind`` events last said one of ``states``."""
    intervals: list[Interval] = []
    since: float | None = None
    for record in records:
        if record.sender != sender or record.kind != kind:
            continue
        inside = str(record.data.get(key, "")) in states
        if inside and since is None:
            since = record.t
        elif not inside and since is not None:
            intervals.append((since, record.t))
            since = None
    if since is not None:
        intervals.append((since, end))
    return intervals


def _series_spans(times: Sequence[float], *, gap: float) -> list[Interval]:
    """First to last of each run of ``times`` with less than ``gap`` seconds between neighbours."""
    spans: list[Interval] = []
    for t in sorted(times):
        if spans and t - spans[-1][1] < gap:
            spans[-1] = (spans[-1][0], t)
        else:
            spans.append((t, t))
    return spans


def _union(intervals: Sequence[Interval]) -> list[Interval]:
    """Sorted and merged (``intersect`` with everything merges what overlaps)."""
    return intersect(intervals, [(-math.inf, math.inf)])


def print_breakdown(seconds: dict[str, float]) -> None:
    """One line per label: clock minutes and share of the good-weather dark time."""
    whole = sum(seconds.values()) or 1.0
    print(f"{'good-weather dark time':28}  {whole / 60:7.1f} min")
    for label, value in seconds.items():
        print(f"  {label:26}  {value / 60:7.1f} min  {100 * value / whole:5.1f} %")


def main() -> int:
    out = Path(sys.argv[1])
    night = read_night(out)
    latitude, longitude = night_site(night)
    print_breakdown(breakdown(night, latitude=latitude, longitude=longitude))
    return 0


if __name__ == "__main__":
    sys.exit(main())
