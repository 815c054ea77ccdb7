"""Small SVG charts for the night report, written by hand (no plotting library needed).

:func:`xy_chart` draws series of points and lines in a box with ticks; :func:`bands` draws
labelled rows of time intervals (the timeline). Both return an ``<svg>`` element as text.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from html import escape

__all__ = ["Band", "Series", "bands", "nice_ticks", "xy_chart"]

WIDTH, HEIGHT = 760, 260
LEFT, RIGHT, TOP, BOTTOM = 60, 16, 14, 40


@dataclass(frozen=True)
class Series:
    """Points (``x``, ``y``) drawn as dots, a line, or both, in ``colour``, named in the legend."""

    name: str
    points: Sequence[tuple[float, float]]
    colour: str = "#1f77b4"
    dots: bool = True
    line: bool = False


@dataclass(frozen=True)
class Band:
    """A row of the timeline: intervals (start, end, label, colour)."""

    name: str
    intervals: Sequence[tuple[float, float, str, str]] = field(default_factory=tuple)


def nice_ticks(low: float, high: float, count: int = 6) -> list[float]:
    """Round tick values covering ``low``..``high``."""
    if not high > low:
        return [low]
    raw = (high - low) / count
    magnitude = 10 ** math.floor(math.log10(raw))
    step = next(m * magnitude for m in (1, 2, 5, 10) if m * magnitude >= raw)
    first = math.ceil(low / step) * step
    return [first + i * step for i in range(int((high - first) / step + 1e-9) + 1)]


def xy_chart(
    series: Sequence[Series],
    *,
    x_label: str,
    y_label: str,
    log_y: bool = False,
    x_format: Callable[[float], str] = lambda v: f"{v:g}",
    x_ticks: Sequence[float] | None = None,
) -> str:
    """A chart of ``series`` (non-finite points are left out; log_y drops y <= 0)."""
    points = [(x, y) for s in series for x, y in s.points if _usable(x, y, log_y)]
    if not points:
        return "<p><em>no data</em></p>"
    fy: Callable[[float], float] = math.log10 if log_y else (lambda v: v)
    x0, x1 = min(p[0] for p in points), max(p[0] for p in points)
    y0, y1 = min(fy(p[1]) for p in points), max(fy(p[1]) for p in points)
    x0, x1 = (x0 - 1, x1 + 1) if x1 == x0 else (x0, x1)
    pad = (y1 - y0) * 0.08 or 1.0
    y0, y1 = y0 - pad, y1 + pad

    def sx(x: float) -> float:
        return LEFT + (x - x0) / (x1 - x0) * (WIDTH - LEFT - RIGHT)

    def sy(y: float) -> float:
        return HEIGHT - BOTTOM - (fy(y) - y0) / (y1 - y0) * (HEIGHT - TOP - BOTTOM)

    parts = [_frame(x_label, y_label)]
    for tick in x_ticks if x_ticks is not None else nice_ticks(x0, x1):
        if x0 <= tick <= x1:
            parts.append(_tick_x(sx(tick), x_format(tick)))
    y_ticks = [10**v for v in nice_ticks(y0, y1, 4)] if log_y else nice_ticks(y0, y1, 5)
    for tick in y_ticks:
        parts.append(_tick_y(sy(tick), f"{tick:.3g}"))
    for index, s in enumerate(series):
        usable = [(sx(x), sy(y)) for x, y in s.points if _usable(x, y, log_y)]
        if s.line and len(usable) > 1:
            path = " ".join(f"{x:.1f},{y:.1f}" for x, y in usable)
            parts.append(f'<polyline points="{path}" fill="none" stroke="{s.colour}" stroke-width="1.5"/>')
        if s.dots:
            parts.extend(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="2.5" fill="{s.colour}"/>' for x, y in usable)
        parts.append(_legend(index, s.name, s.colour))
    return _svg(parts)


def bands(
    rows: Sequence[Band],
    *,
    start: float,
    end: float,
    x_format: Callable[[float], str],
    x_ticks: Sequence[float],
) -> str:
    """A timeline: one labelled row per band, its intervals as coloured boxes with a tooltip."""
    row_height, label_width = 22, 110
    height = TOP + row_height * len(rows) + BOTTOM

    def sx(t: float) -> float:
        return label_width + (t - start) / max(1.0, end - start) * (WIDTH - label_width - RIGHT)

    parts = []
    for index, row in enumerate(rows):
        y = TOP + index * row_height
        parts.append(f'<text x="4" y="{y + 15}" font-size="12">{escape(row.name)}</text>')
        parts.append(
            f'<rect x="{label_width}" y="{y + 2}" width="{WIDTH - label_width - RIGHT}" height="18" '
            'fill="#f4f4f4"/>'
        )
        for a, b, label, colour in row.intervals:
            left, right = sx(max(a, start)), sx(min(b, end))
            parts.append(
                f'<rect x="{left:.1f}" y="{y + 2}" width="{max(0.8, right - left):.1f}" height="18" '
                f'fill="{colour}"><title>{escape(label)}</title></rect>'
            )
    base = TOP + row_height * len(rows)
    for tick in x_ticks:
        x = sx(tick)
        parts.append(
            f'<line x1="{x:.1f}" y1="{TOP}" x2="{x:.1f}" y2="{base + 4}" stroke="#999" stroke-width="0.5"/>'
        )
        parts.append(
            f'<text x="{x:.1f}" y="{base + 18}" font-size="11" text-anchor="middle">'
            f"{escape(x_format(tick))}</text>"
        )
    return _svg(parts, height)


def _usable(x: float, y: float, log_y: bool) -> bool:
    return math.isfinite(x) and math.isfinite(y) and (y > 0 or not log_y)


def _frame(x_label: str, y_label: str) -> str:
    width, height = WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM
    box = f'<rect x="{LEFT}" y="{TOP}" width="{width}" height="{height}" fill="none" stroke="#333"/>'
    x_text = (
        f'<text x="{LEFT + width / 2}" y="{HEIGHT - 6}" font-size="12" text-anchor="middle">'
        f"{escape(x_label)}</text>"
    )
    middle = (TOP + HEIGHT - BOTTOM) / 2
    y_text = (
        f'<text x="14" y="{middle}" font-size="12" text-anchor="middle" '
        f'transform="rotate(-90 14 {middle})">{escape(y_label)}</text>'
    )
    return box + x_text + y_text


def _tick_x(x: float, label: str) -> str:
    bottom = HEIGHT - BOTTOM
    return (
        f'<line x1="{x:.1f}" y1="{bottom}" x2="{x:.1f}" y2="{bottom + 4}" stroke="#333"/>'
        f'<text x="{x:.1f}" y="{bottom + 16}" font-size="11" text-anchor="middle">{escape(label)}</text>'
    )


def _tick_y(y: float, label: str) -> str:
    return (
        f'<line x1="{LEFT - 4}" y1="{y:.1f}" x2="{LEFT}" y2="{y:.1f}" stroke="#333"/>'
        f'<text x="{LEFT - 6}" y="{y + 4:.1f}" font-size="11" text-anchor="end">{escape(label)}</text>'
    )


def _legend(index: int, name: str, colour: str) -> str:
    x, y = LEFT + 10, TOP + 14 + 15 * index
    return (
        f'<rect x="{x}" y="{y - 9}" width="10" height="10" fill="{colour}"/>'
        f'<text x="{x + 14}" y="{y}" font-size="11">{escape(name)}</text>'
    )


def _svg(parts: Sequence[str], height: int = HEIGHT) -> str:
    body = "".join(parts)
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{height}" '
        f'viewBox="0 0 {WIDTH} {height}" font-family="sans-serif">{body}</svg>'
    )
