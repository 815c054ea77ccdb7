"""The night's numbers, from the records (pure: intervals in Unix seconds in, numbers out).

* **Roof open**: the part of the good-weather dark time (Sun below ``sun_limit``, weather not bad)
  in which the roof (the observatory's shutter) was open.
* **Camera shutter open**: the part of the good-weather dark time covered by light exposures while
  the roof was open (a frame cut short by bad weather counts up to the roof's closing, and only the
  seconds its header says it exposed).
* **Exposures while closed**: light frames whose exposure is not inside a roof-open interval.
* **Roof-close delay**: from each BadWeatherEvent that found the roof open to the next
  RoofClosedEvent.
* **Task outcomes**: every started task ended done, or failed with a reason.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from nightcrew.astro import sun_altitude
from nightcrew.report._data import (
    Frame,
    Night,
    Record,
    TaskRun,
    bad_weather_intervals,
    roof_open_intervals,
    task_runs,
)

__all__ = [
    "NightNumbers",
    "dark_intervals",
    "exposures_while_closed",
    "good_dark_intervals",
    "intersect",
    "light_intervals",
    "night_numbers",
    "roof_close_delays",
    "subtract",
    "total",
    "union",
]

Interval = tuple[float, float]


@dataclass(frozen=True)
class NightNumbers:
    """The night in numbers (times in clock seconds)."""

    good_dark_s: float
    roof_open_s: float
    shutter_open_s: float
    light_frames_while_closed: int
    science_frames_while_closed: int
    roof_close_delays_s: tuple[float, ...]
    tasks: tuple[TaskRun, ...]

    @property
    def roof_open_fraction(self) -> float:
        return self.roof_open_s / self.good_dark_s if self.good_dark_s > 0 else 0.0

    @property
    def shutter_open_fraction(self) -> float:
        return self.shutter_open_s / self.good_dark_s if self.good_dark_s > 0 else 0.0

    @property
    def tasks_without_reason(self) -> tuple[TaskRun, ...]:
        """Started tasks that neither ended done nor failed with a reason."""
        return tuple(
            t for t in self.tasks if not (t.outcome == "done" or (t.outcome == "failed" and t.reason))
        )


def night_numbers(
    night: Night, *, latitude: float, longitude: float, sun_limit: float = -12.0
) -> NightNumbers:
    end = night.span[1]
    roof = roof_open_intervals(night.records, end)
    good_dark = good_dark_intervals(night, latitude=latitude, longitude=longitude, sun_limit=sun_limit)
    closed = exposures_while_closed(night.frames, roof)
    return NightNumbers(
        good_dark_s=total(good_dark),
        roof_open_s=total(intersect(roof, good_dark)),
        shutter_open_s=total(intersect(light_intervals(night.frames, roof), good_dark)),
        light_frames_while_closed=len(closed),
        science_frames_while_closed=sum(1 for f in closed if f.image_type == "object"),
        roof_close_delays_s=tuple(roof_close_delays(night.records)),
        tasks=tuple(task_runs(night.records)),
    )


def good_dark_intervals(
    night: Night, *, latitude: float, longitude: float, sun_limit: float = -12.0
) -> list[Interval]:
    """The good-weather dark time: the Sun below ``sun_limit`` and the weather not bad."""
    start, end = night.span
    dark = dark_intervals(latitude, longitude, start, end, sun_limit)
    return subtract(dark, bad_weather_intervals(night.records, end))


def dark_intervals(
    latitude: float, longitude: float, start: float, end: float, sun_limit: float, step: float = 60.0
) -> list[Interval]:
    """When the Sun is below ``sun_limit`` between ``start`` and ``end`` (to ``step`` seconds)."""
    intervals: list[Interval] = []
    since: float | None = None
    t = start
    while t <= end:
        dark = sun_altitude(latitude, longitude, t) < sun_limit
        if dark and since is None:
            since = t
        elif not dark and since is not None:
            intervals.append((since, t))
            since = None
        t += step
    if since is not None:
        intervals.append((since, end))
    return intervals


def light_intervals(frames: Sequence[Frame], roof_open: Sequence[Interval]) -> list[Interval]:
    """When light reached the chip: light frames' exposures, only while the roof was open."""
    return intersect(union([(f.start, f.end) for f in frames if f.light and f.exposure_time > 0]), roof_open)


def exposures_while_closed(frames: Sequence[Frame], roof_open: Sequence[Interval]) -> list[Frame]:
    """Light frames not exposed wholly inside one roof-open interval."""
    return [
        f for f in frames if f.light and not any(a <= f.start and f.end <= b + 1e-3 for a, b in roof_open)
    ]


def roof_close_delays(records: Sequence[Record]) -> list[float]:
    """Seconds from each BadWeatherEvent that found the roof open (or opening) to RoofClosedEvent."""
    delays: list[float] = []
    roof_open = False
    waiting_since: float | None = None
    for record in records:
        if record.kind in ("RoofOpenedEvent", "RoofOpeningEvent"):
            roof_open = True
        elif record.kind == "BadWeatherEvent" and roof_open and waiting_since is None:
            waiting_since = record.t
        elif record.kind == "RoofClosedEvent":
            roof_open = False
            if waiting_since is not None:
                delays.append(record.t - waiting_since)
                waiting_since = None
    return delays


def total(intervals: Sequence[Interval]) -> float:
    return sum(b - a for a, b in intervals if b > a)


def union(intervals: Sequence[Interval]) -> list[Interval]:
    """Sorted, with overlapping and touching intervals merged."""
    merged: list[Interval] = []
    for a, b in sorted(intervals):
        if merged and a <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], b))
        else:
            merged.append((a, b))
    return merged


def intersect(first: Sequence[Interval], second: Sequence[Interval]) -> list[Interval]:
    """The parts common to both (each a list of disjoint intervals)."""
    result = []
    for a, b in first:
        for c, d in second:
            low, high = max(a, c), min(b, d)
            if high > low:
                result.append((low, high))
    return union(result)


def subtract(intervals: Sequence[Interval], removed: Sequence[Interval]) -> list[Interval]:
    """``intervals`` without the parts in ``removed``."""
    result = list(intervals)
    for c, d in removed:
        pieces = []
        for a, b in result:
            if d <= a or c >= b:
                pieces.append((a, b))
                continue
            if a < c:
                pieces.append((a, c))
            if d < b:
                pieces.append((d, b))
        result = pieces
    return result
