"""The sections of the night report, each a function of the night's data returning HTML."""

from __future__ import annotations

import math
from collections.abc import Sequence
from datetime import UTC, datetime
from html import escape
from typing import Any

from nightcrew.astro import sun_altitude
from nightcrew.report._data import Frame, Night, bad_weather_intervals, roof_open_intervals
from nightcrew.report._metrics import NightNumbers
from nightcrew.report._svg import Band, Series, bands, xy_chart
from nightcrew.report._time_budget import Acquisition
from nightcrew.report.records import FOCUS_SERIES, SCHEDULE_RECORD

__all__ = [
    "focus_section",
    "frames_section",
    "guiding_section",
    "scheduler_section",
    "summary_section",
    "tasks_section",
    "time_budget_section",
    "timeline_section",
]

OUTCOME_COLOURS = {"done": "#2ca02c", "failed": "#d62728", "running": "#ff7f0e"}
FRAME_COLOURS = {
    "object": "#1f77b4",
    "skyflat": "#bcbd22",
    "focus": "#9467bd",
    "bias": "#7f7f7f",
    "dark": "#444",
    "acquisition": "#e377c2",
}
#: Frames of any other IMAGETYP.
OTHER_FRAME_COLOUR = "#17becf"
#: Idle and lost time in warm colours, so that they stand out in the bar.
BUDGET_COLOURS = {
    "dark and bias frames": "#636363",
    "exposing, frame not kept": "#e7ba52",
    "readout": "#aec7e8",
    "slew": "#8c564b",
    "roof opening or closing": "#bcbd22",
    "roof closed": "#7f7f7f",
    "filter change": "#9edae5",
    "focus run, between frames": "#c5b0d5",
    "in a task, camera idle": "#ff7f0e",
    "no task running": "#d62728",
}


def clock(t: float) -> str:
    return datetime.fromtimestamp(t, tz=UTC).strftime("%H:%M")


def _hour_ticks(start: float, end: float) -> list[float]:
    first = math.ceil(start / 3600.0) * 3600.0
    step = 3600.0 if end - start <= 8 * 3600 else 7200.0
    return [first + i * step for i in range(int((end - first) / step) + 1)]


def summary_section(numbers: NightNumbers, night: Night) -> str:
    outcomes: dict[str, int] = {}
    for task in numbers.tasks:
        outcomes[task.outcome] = outcomes.get(task.outcome, 0) + 1
    delays = (
        ", ".join(f"{d:.0f} s" for d in numbers.roof_close_delays_s) or "no bad weather with the roof open"
    )
    rows = [
        ("Good-weather dark time (Sun < -12°)", f"{numbers.good_dark_s / 3600:.2f} h"),
        ("Roof open in it", _part(numbers.roof_open_s, numbers.roof_open_fraction)),
        (
            "Camera shutter open in it (exposing)",
            _part(numbers.shutter_open_s, numbers.shutter_open_fraction),
        ),
        ("Frames", f"{len(night.frames)}"),
        ("Science frames while the roof was closed", f"{numbers.science_frames_while_closed}"),
        ("Light frames while the roof was closed", f"{numbers.light_frames_while_closed}"),
        ("Roof closed after bad weather", delays),
        ("Task runs", ", ".join(f"{n} {k}" for k, n in sorted(outcomes.items())) or "none"),
        ("Task runs without a done/failed-with-reason end", f"{len(numbers.tasks_without_reason)}"),
    ]
    return _table(("", ""), rows, header=False)


def _part(seconds: float, fraction: float) -> str:
    return f"{seconds / 3600:.2f} h ({100 * fraction:.1f} %)"


def timeline_section(night: Night, numbers: NightNumbers, latitude: float, longitude: float) -> str:
    start, end = night.span
    if end <= start:
        return "<p><em>no records</em></p>"
    ticks = _hour_ticks(start, end)
    sun_rows = []
    step = 300.0
    t = start
    while t < end:
        altitude = sun_altitude(latitude, longitude, t)
        shade = (
            "#fdd835"
            if altitude > 0
            else "#90caf9"
            if altitude > -6
            else "#42a5f5"
            if altitude > -12
            else "#1565c0"
            if altitude > -18
            else "#0d2a5c"
        )
        sun_rows.append((t, min(end, t + step), f"{clock(t)} Sun {altitude:.1f}°", shade))
        t += step
    rows = [
        Band("Sun", sun_rows),
        Band(
            "Bad weather",
            [
                (a, b, f"bad {clock(a)}-{clock(b)}", "#d62728")
                for a, b in bad_weather_intervals(night.records, end)
            ],
        ),
        Band(
            "Roof open",
            [
                (a, b, f"open {clock(a)}-{clock(b)}", "#2ca02c")
                for a, b in roof_open_intervals(night.records, end)
            ],
        ),
        Band(
            "Tasks",
            [
                (
                    r.start,
                    r.end or end,
                    f"{r.name}: {r.outcome} {r.reason}".strip(),
                    OUTCOME_COLOURS.get(r.outcome, "#999"),
                )
                for r in numbers.tasks
            ],
        ),
        Band(
            "Exposures",
            [
                (
                    f.start,
                    f.end,
                    f"{f.name} ({f.image_type} {f.exposure_time:g} s)",
                    FRAME_COLOURS.get(f.image_type, OTHER_FRAME_COLOUR),
                )
                for f in night.frames
            ],
        ),
    ]
    timeline = bands(rows, start=start, end=end, x_format=clock, x_ticks=ticks)
    sun = Series(
        "Sun altitude",
        [(t, sun_altitude(latitude, longitude, t)) for t in _steps(start, end, 600.0)],
        colour="#ff7f0e",
        dots=False,
        line=True,
    )
    chart = xy_chart([sun], x_label="UTC", y_label="Sun altitude [deg]", x_format=clock, x_ticks=ticks)
    legend = " ".join(
        f'<span class="key" style="background:{c}"></span>{escape(k)}'
        for k, c in {**OUTCOME_COLOURS, **FRAME_COLOURS}.items()
    )
    return f"{timeline}<p class='legend'>{legend}</p>{chart}"


def _steps(start: float, end: float, step: float) -> list[float]:
    return [start + i * step for i in range(int((end - start) / step) + 1)]


def tasks_section(numbers: NightNumbers) -> str:
    rows = [
        (r.task_id, r.name, clock(r.start), clock(r.end) if r.end else "-", r.outcome, r.reason)
        for r in numbers.tasks
    ]
    return _table(("id", "task", "start", "end", "outcome", "reason"), rows)


def cadences_section(cadences: Sequence[tuple[str, str]]) -> str:
    """Each cadence's progress: ``(name, progress)`` pairs as the task archive tells them."""
    return _table(("cadence", "progress"), cadences)


def time_budget_section(spent: dict[str, float], runs: Sequence[Acquisition]) -> str:
    """The dark time per label as a bar and a table, then each run's time to its first science frame."""
    whole = sum(spent.values())
    if whole <= 0:
        return "<p><em>no good-weather dark time</em></p>"
    colours = {k: FRAME_COLOURS.get(k.removeprefix("exposing "), OTHER_FRAME_COLOUR) for k in spent}
    colours |= BUDGET_COLOURS
    shown = [k for k, v in spent.items() if v > 0]
    intervals, at = [], 0.0
    for label in shown:
        tip = f"{label}: {spent[label] / 60:.1f} min ({100 * spent[label] / whole:.1f} %)"
        intervals.append((at, at + spent[label], tip, colours[label]))
        at += spent[label]
    bar = bands(
        [Band("dark time", intervals)],
        start=0.0,
        end=whole,
        x_format=lambda v: f"{100 * v / whole:.0f} %",
        x_ticks=[whole * i / 4 for i in range(5)],
    )
    legend = " ".join(f'<span class="key" style="background:{colours[k]}"></span>{escape(k)}' for k in shown)
    rows = [(k, f"{spent[k] / 60:.1f}", f"{100 * spent[k] / whole:.1f}") for k in shown]
    budget = _table(("good-weather dark time", "min", "%"), [*rows, ("all", f"{whole / 60:.1f}", "100")])
    return f"{bar}<p class='legend'>{legend}</p>{budget}{_acquisition_table(runs)}"


def _acquisition_table(runs: Sequence[Acquisition]) -> str:
    if not runs:
        return "<p><em>no task took a science frame</em></p>"
    rows = []
    for run in runs:
        slew, busy = f"{run.slewing_s:.0f}", f"{run.camera_busy_s:.0f}"
        if run.seconds is None:
            rows.append((run.task_id, run.name, clock(run.start), "no science frame", slew, busy, ""))
        else:
            other = f"{run.seconds - run.slewing_s - run.camera_busy_s:.0f}"
            rows.append((run.task_id, run.name, clock(run.start), f"{run.seconds:.0f}", slew, busy, other))
    head = ("id", "task", "start", "to first science frame [s]", "slewing [s]", "camera busy [s]", "rest [s]")
    note = (
        "<p>From each task's start to the start of its first science exposure (clock seconds): "
        "slewing, the camera busy (acquisition or focus frames), and the rest (solving acquisition "
        "frames, analysing focus frames, filter changes, waiting). A task that failed before its "
        "first science frame counts to its end.</p>"
    )
    return note + _table(head, rows)


def scheduler_section(night: Night, numbers: NightNumbers) -> str:
    plans = night.of(SCHEDULE_RECORD)
    if not plans:
        return "<p><em>no plans recorded</em></p>"
    rows = []
    for plan in plans:
        data = plan.data
        bound, objective = data.get("bound"), float(data.get("objective", 0.0))
        gap = f"{100 * (bound - objective) / bound:.2f} %" if bound else "-"
        rows.append(
            (
                clock(plan.t),
                str(len(data.get("slots", []))),
                f"{objective:.3f}",
                f"{bound:.3f}" if bound is not None else "-",
                gap,
                str(data.get("status", "")),
            )
        )
    first = plans[0].data.get("slots", [])
    scheduled = {s["task"] for s in first}
    done = {t.task_id for t in numbers.tasks if t.outcome == "done"}
    observed_s = sum((t.end or t.start) - t.start for t in numbers.tasks if t.outcome == "done")
    planned_s = sum(_seconds(s["end"]) - _seconds(s["start"]) for s in first)
    summary = _table(
        ("", ""),
        [
            ("Tasks in the first plan", f"{len(scheduled)} ({planned_s / 3600:.2f} h)"),
            (
                "Tasks done",
                f"{len(done)} ({observed_s / 3600:.2f} h), {len(done & scheduled)} of them in the first plan",
            ),
            ("Plans made", str(len(plans))),
        ],
        header=False,
    )
    table = _table(("planned at", "blocks", "objective", "bound", "gap", "status"), rows)
    return summary + table


def _seconds(text: str) -> float:
    return datetime.fromisoformat(text).timestamp()


def focus_section(night: Night) -> str:
    parts = []
    for record in night.of(FOCUS_SERIES):
        measurements = [(float(p), float(w)) for p, w in record.data.get("measurements", [])]
        series = [Series("measured FWHM", measurements)]
        failed = record.data.get("failed")
        if failed is not None:  # no best focus, the focus stayed as it was: no refused fit drawn
            caption = f"{clock(record.t)}: focus series failed: {failed}"
        else:
            best, error = record.data.get("focus", math.nan), record.data.get("error", math.nan)
            fit, note = _hyperbola(measurements)
            caption = f"{clock(record.t)}: best focus {best:.3f} ± {error:.3f} mm{note}"
            if fit is not None:
                series.append(fit)
        parts.append(
            f"<p>{escape(caption)}</p>" + xy_chart(series, x_label="focus [mm]", y_label="FWHM [px]")
        )
    return "".join(parts) or "<p><em>no focus series succeeded</em></p>"


def _hyperbola(measurements: list[tuple[float, float]]) -> tuple[Series | None, str]:
    """The fitted curve through a series' (position, width) points, or None and why not."""
    from nightcrew.focus import FocusSeriesError, fit_focus_hyperbola

    positions = [p for p, _ in measurements]
    try:
        fit = fit_focus_hyperbola(positions, [w for _, w in measurements])
    except FocusSeriesError as exc:
        return None, f" (no fit here: {exc})"
    grid = _steps(min(positions), max(positions), (max(positions) - min(positions)) / 60 or 1.0)
    curve = [(f, math.hypot(fit.min_width, fit.slope * (f - fit.focus))) for f in grid]
    return Series("hyperbola fit", curve, colour="#d62728", dots=False, line=True), ""


def flats_section(fits: dict[tuple[str, str], Any]) -> str:
    if not fits:
        return "<p><em>no usable sky flats</em></p>"
    colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#8c564b"]
    series = []
    captions = []
    for index, ((filter_name, binning), fit) in enumerate(sorted(fits.items())):
        colour = colours[index % len(colours)]
        series.append(
            Series(
                f"{filter_name} {binning}",
                list(zip(fit.altitudes.tolist(), fit.times.tolist(), strict=True)),
                colour,
            )
        )
        low, high = float(fit.altitudes.min()), float(fit.altitudes.max())
        grid = _steps(low, high, (high - low) / 40 or 1.0)
        series.append(
            Series(fit.expression, [(h, float(fit(h))) for h in grid], colour, dots=False, line=True)
        )
        captions.append(
            f"{filter_name} {binning}: t = {fit.expression}, {len(fit.altitudes)} flats, "
            f"rms {100 * fit.rms:.1f} %"
        )
    chart = xy_chart(
        series, x_label="solar altitude h [deg]", y_label="exposure time for the target [s]", log_y=True
    )
    return chart + "".join(f"<p>{escape(c)}</p>" for c in captions)


def guiding_section(frames: Sequence[Frame]) -> str:
    guided = [(f.start, f.guide_rms) for f in frames if f.guide_rms is not None]
    if not guided:
        return "<p><em>no guided frames (GUIDRMS)</em></p>"
    values = sorted(v for _, v in guided if v is not None)
    median = values[len(values) // 2]
    chart = xy_chart(
        [Series("GUIDRMS", [(t, v) for t, v in guided if v is not None])],
        x_label="UTC",
        y_label="guiding RMS [arcsec]",
        x_format=clock,
        x_ticks=_hour_ticks(guided[0][0], guided[-1][0] + 1),
    )
    return f"<p>{len(values)} guided frames, median RMS {median:.2f}″</p>{chart}"


def frames_section(frames: Sequence[Frame], thumbnails: dict[str, str]) -> str:
    rows = []
    for f in frames:
        thumb = thumbnails.get(f.name)
        image = f'<img src="{escape(thumb)}" width="96" height="96" alt="">' if thumb else ""
        rows.append(
            "<tr>"
            + "".join(
                f"<td>{cell}</td>"
                for cell in (
                    image,
                    escape(f.name),
                    clock(f.start),
                    escape(f.image_type),
                    escape(f.filter_name),
                    f"{f.exposure_time:g}",
                    escape(f.task),
                    f"{f.guide_rms:.2f}" if f.guide_rms is not None else "",
                )
            )
            + "</tr>"
        )
    head = "".join(f"<th>{h}</th>" for h in ("", "file", "UTC", "type", "filter", "s", "task", "GUIDRMS"))
    return f"<table><tr>{head}</tr>{''.join(rows)}</table>"


def _table(head: Sequence[str], rows: Sequence[Sequence[str]], header: bool = True) -> str:
    top = "<tr>" + "".join(f"<th>{escape(h)}</th>" for h in head) + "</tr>" if header else ""
    body = "".join("<tr>" + "".join(f"<td>{escape(str(c))}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table>{top}{body}</table>"
