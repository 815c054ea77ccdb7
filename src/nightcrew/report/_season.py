"""A season of nights in numbers: one row per night from its records and frames, and the totals.

Pure: a :class:`~nightcrew.report._data.Night` in, a :class:`SeasonNight` out; the table is plain
text (Markdown), so a benchmark prints it and a season directory keeps it (season.md).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, fields
from typing import Any

from nightcrew.report._data import Night
from nightcrew.report._metrics import night_numbers
from nightcrew.report._time_budget import time_budget
from nightcrew.report.records import SCHEDULE_RECORD

__all__ = [
    "DELAY_BINS_S",
    "SeasonNight",
    "season_night",
    "season_night_from",
    "season_row",
    "season_summary",
    "season_table",
]

#: Upper edges (s) of the roof-close delay distribution; the last bin is everything above.
DELAY_BINS_S = (15.0, 30.0, 60.0, 120.0)


@dataclass(frozen=True)
class SeasonNight:
    """One night of a season (times in clock seconds)."""

    night: str
    good_dark_s: float
    roof_open_s: float
    shutter_open_s: float
    bad_weather_onsets: int
    roof_close_delays_s: tuple[float, ...]
    light_frames_while_closed: int
    science_frames_while_closed: int
    tasks_done: int
    tasks_failed: int
    tasks_unfinished: int
    objective: float | None
    bound: float | None
    #: Where the good-weather dark time went (:func:`~nightcrew.report.time_budget`), clock seconds.
    dark_time: dict[str, float] = field(default_factory=dict)

    @property
    def shutter_fraction(self) -> float:
        return self.shutter_open_s / self.good_dark_s if self.good_dark_s > 0 else 0.0


def season_night(name: str, night: Night, *, latitude: float, longitude: float) -> SeasonNight:
    """The numbers of one night (``name``, e.g. its date); the plan is the night's first."""
    numbers = night_numbers(night, latitude=latitude, longitude=longitude)
    outcomes = [t.outcome for t in numbers.tasks]
    plans = night.of(SCHEDULE_RECORD)
    first = plans[0].data if plans else {}
    objective, bound = first.get("objective"), first.get("bound")
    return SeasonNight(
        night=name,
        good_dark_s=numbers.good_dark_s,
        roof_open_s=numbers.roof_open_s,
        shutter_open_s=numbers.shutter_open_s,
        bad_weather_onsets=len(night.of("BadWeatherEvent")),
        roof_close_delays_s=numbers.roof_close_delays_s,
        light_frames_while_closed=numbers.light_frames_while_closed,
        science_frames_while_closed=numbers.science_frames_while_closed,
        tasks_done=outcomes.count("done"),
        tasks_failed=outcomes.count("failed"),
        tasks_unfinished=len(outcomes) - outcomes.count("done") - outcomes.count("failed"),
        objective=None if objective is None else float(objective),
        bound=None if bound is None else float(bound),
        dark_time=time_budget(night, latitude=latitude, longitude=longitude),
    )


def season_row(night: SeasonNight) -> dict[str, Any]:
    """One night as JSON-ready values (a row of season.json; :func:`season_night_from` reads it)."""
    return {**asdict(night), "shutter_fraction": night.shutter_fraction}


def season_night_from(row: Mapping[str, Any]) -> SeasonNight:
    """The night of a row made by :func:`season_row` (e.g. read back from JSON)."""
    values = {f.name: row[f.name] for f in fields(SeasonNight) if f.name in row}
    values["roof_close_delays_s"] = tuple(values.get("roof_close_delays_s", ()))
    return SeasonNight(**values)


def season_summary(nights: Sequence[SeasonNight]) -> dict[str, Any]:
    """Totals over ``nights`` (JSON-ready), with the per-night rows under ``nights``."""
    delays = [d for n in nights for d in n.roof_close_delays_s]
    good_dark = sum(n.good_dark_s for n in nights)
    shutter = sum(n.shutter_open_s for n in nights)
    edges = (0.0, *DELAY_BINS_S)
    distribution = {
        f"<= {high:g} s": sum(1 for d in delays if low < d <= high)
        for low, high in zip(edges[:-1], DELAY_BINS_S, strict=True)
    }
    distribution[f"> {DELAY_BINS_S[-1]:g} s"] = sum(1 for d in delays if d > DELAY_BINS_S[-1])
    dark_time: dict[str, float] = {}
    for n in nights:
        for label, seconds in n.dark_time.items():
            dark_time[label] = dark_time.get(label, 0.0) + seconds
    return {
        "nights": [season_row(n) for n in nights],
        "good_dark_h": good_dark / 3600.0,
        "shutter_fraction": shutter / good_dark if good_dark > 0 else 0.0,
        "bad_weather_onsets": sum(n.bad_weather_onsets for n in nights),
        "roof_close_delays": len(delays),
        "roof_close_delay_max_s": max(delays, default=0.0),
        "roof_close_delay_distribution": distribution,
        "light_frames_while_closed": sum(n.light_frames_while_closed for n in nights),
        "science_frames_while_closed": sum(n.science_frames_while_closed for n in nights),
        "tasks_done": sum(n.tasks_done for n in nights),
        "tasks_failed": sum(n.tasks_failed for n in nights),
        "tasks_unfinished": sum(n.tasks_unfinished for n in nights),
        "objective": sum(n.objective or 0.0 for n in nights),
        "bound": sum(n.bound or 0.0 for n in nights),
        "dark_time_s": dark_time,
    }


def season_table(nights: Sequence[SeasonNight]) -> str:
    """The season as a Markdown table (a row per night and the total) and the delay distribution."""
    head = (
        "| night | good dark h | shutter % | bad-weather onsets | roof-close delay max s "
        "| light/science frames roof closed | tasks done/failed/unfinished | objective / bound |"
    )
    lines = [head, "|" + "---|" * 8]
    for n in nights:
        lines.append(
            _row(
                n.night,
                n.good_dark_s / 3600.0,
                n.shutter_fraction,
                n.bad_weather_onsets,
                max(n.roof_close_delays_s, default=None),
                (n.light_frames_while_closed, n.science_frames_while_closed),
                (n.tasks_done, n.tasks_failed, n.tasks_unfinished),
                (n.objective, n.bound),
            )
        )
    total = season_summary(nights)
    lines.append(
        _row(
            f"**all {len(nights)}**",
            total["good_dark_h"],
            total["shutter_fraction"],
            total["bad_weather_onsets"],
            total["roof_close_delay_max_s"] if total["roof_close_delays"] else None,
            (total["light_frames_while_closed"], total["science_frames_while_closed"]),
            (total["tasks_done"], total["tasks_failed"], total["tasks_unfinished"]),
            (total["objective"], total["bound"]),
        )
    )
    spread = ", ".join(f"{k}: {v}" for k, v in total["roof_close_delay_distribution"].items())
    lines += ["", f"Roof-close delays after bad-weather onsets ({total['roof_close_delays']}): {spread}"]
    return "\n".join([*lines, "", *_dark_time_table(total["dark_time_s"])]) + "\n"


def _dark_time_table(spent: dict[str, float]) -> list[str]:
    """Where the season's good-weather dark time went: exposing, and each cause of the shutter closed."""
    whole = sum(spent.values())
    if whole <= 0:
        return ["No good-weather dark time."]
    closed = sum(v for k, v in spent.items() if not k.startswith("exposing "))
    lines = [
        f"Where the good-weather dark time went ({whole / 3600:.2f} h; shutter closed "
        f"{closed / 3600:.2f} h = {100 * closed / whole:.1f} %):",
        "",
        "| | h | % of good dark | % of shutter closed |",
        "|---|---|---|---|",
    ]
    for label, seconds in spent.items():
        kept = label.startswith("exposing ")
        share = "" if kept or closed <= 0 else f"{100 * seconds / closed:.1f}"
        lines.append(f"| {label} | {seconds / 3600:.2f} | {100 * seconds / whole:.1f} | {share} |")
    return lines


def _row(
    name: str,
    dark_h: float,
    shutter: float,
    onsets: int,
    max_delay: float | None,
    closed: tuple[int, int],
    tasks: tuple[int, int, int],
    plan: tuple[float | None, float | None],
) -> str:
    delay = "-" if max_delay is None else f"{max_delay:.1f}"
    objective, bound = plan
    score = "-" if objective is None or not bound else f"{objective:.2f} / {bound:.2f}"
    return (
        f"| {name} | {dark_h:.2f} | {100 * shutter:.1f} | {onsets} | {delay} | {closed[0]}/{closed[1]} "
        f"| {tasks[0]}/{tasks[1]}/{tasks[2]} | {score} |"
    )
