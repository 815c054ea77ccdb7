"""Search parameters (the LCO archive's ``/frames/?...`` style) → one SQL query, checked first.

Every parameter is optional; an unknown one, or one out of range, is refused with 400 naming it.
A cone (``ra``, ``dec``, ``radius`` in degrees) is a band of declination (indexed) and a test on
unit vectors stored with each frame, which both SQLite and PostgreSQL evaluate without trigonometry.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

from nightcrew.services.archive._errors import Rejected

__all__ = ["MAX_LIMIT", "SearchQuery", "parse_search", "unit_vector"]

MAX_LIMIT = 1000
_TEXT = {
    "OBJECT": "object",
    "FILTER": "filter",
    "INSTRUME": "instrument",
    "PROPID": "proposal",
    "TASK": "task",
    "basename": "basename",
}
_LOWER = {"IMAGETYP": "imagetyp", "OBSTYPE": "imagetyp"}
_ORDERING = {
    "DATE_OBS": "obs_time ASC, id ASC",
    "-DATE_OBS": "obs_time DESC, id DESC",
    "id": "id ASC",
    "-id": "id DESC",
}
_OTHER = {
    "start",
    "end",
    "RLEVEL",
    "EXPTIME_MIN",
    "EXPTIME_MAX",
    "ra",
    "dec",
    "radius",
    "limit",
    "offset",
    "ordering",
}
KNOWN = frozenset(_TEXT) | frozenset(_LOWER) | _OTHER


@dataclass
class SearchQuery:
    """WHERE clause, its parameters, ORDER BY, LIMIT and OFFSET of a search."""

    conditions: list[str] = field(default_factory=list)
    params: list[Any] = field(default_factory=list)
    order: str = _ORDERING["-DATE_OBS"]
    limit: int = 100
    offset: int = 0

    def where(self) -> str:
        return " WHERE " + " AND ".join(self.conditions) if self.conditions else ""

    def add(self, condition: str, *params: Any) -> None:
        self.conditions.append(condition)
        self.params.extend(params)


def unit_vector(ra: float, dec: float) -> tuple[float, float, float]:
    """The direction (degrees in) as x, y, z on the unit sphere."""
    a, d = math.radians(ra), math.radians(dec)
    return math.cos(d) * math.cos(a), math.cos(d) * math.sin(a), math.sin(d)


def parse_search(params: Mapping[str, str]) -> SearchQuery:
    """The query for these parameters, or Rejected(400) naming the first bad one."""
    unknown = sorted(set(params) - KNOWN)
    if unknown:
        raise Rejected(400, f"unknown search parameter {unknown[0]!r} (known: {', '.join(sorted(KNOWN))})")
    query = SearchQuery()
    start, end = _time(params, "start"), _time(params, "end")
    if start is not None and end is not None and start >= end:
        raise Rejected(400, f"start ({params['start']}) must be before end ({params['end']})")
    if start is not None:
        query.add("obs_time >= ?", start)
    if end is not None:
        query.add("obs_time < ?", end)
    for name, column in _TEXT.items():
        if params.get(name):
            query.add(f"{column} = ?", params[name])
    for name, column in _LOWER.items():
        if params.get(name):
            query.add(f"{column} = ?", params[name].strip().lower())
    if "RLEVEL" in params:
        query.add("rlevel = ?", _number(params, "RLEVEL", int, 0, 255))
    if "EXPTIME_MIN" in params:
        query.add("exptime >= ?", _number(params, "EXPTIME_MIN", float, 0.0, 1e7))
    if "EXPTIME_MAX" in params:
        query.add("exptime <= ?", _number(params, "EXPTIME_MAX", float, 0.0, 1e7))
    _cone(params, query)
    query.limit = _number(params, "limit", int, 1, MAX_LIMIT) if "limit" in params else 100
    query.offset = _number(params, "offset", int, 0, 10**9) if "offset" in params else 0
    ordering = params.get("ordering", "-DATE_OBS")
    if ordering not in _ORDERING:
        raise Rejected(400, f"ordering must be one of {', '.join(_ORDERING)}, got {ordering!r}")
    query.order = _ORDERING[ordering]
    return query


def _cone(params: Mapping[str, str], query: SearchQuery) -> None:
    given = [name for name in ("ra", "dec", "radius") if name in params]
    if not given:
        return
    if len(given) < 3:
        raise Rejected(400, "a cone search needs all of ra, dec and radius (degrees)")
    ra = _number(params, "ra", float, 0.0, 360.0)
    dec = _number(params, "dec", float, -90.0, 90.0)
    radius = _number(params, "radius", float, 0.0, 180.0)
    if radius == 0 or ra == 360.0:
        raise Rejected(400, "radius must be > 0 and ra < 360 degrees")
    x, y, z = unit_vector(ra, dec)
    query.add("dec BETWEEN ? AND ?", max(-90.0, dec - radius), min(90.0, dec + radius))
    query.add("cx * ? + cy * ? + cz * ? >= ?", x, y, z, math.cos(math.radians(radius)))


def _time(params: Mapping[str, str], name: str) -> float | None:
    if not params.get(name):
        return None
    try:
        parsed = datetime.fromisoformat(params[name].strip().replace("Z", "+00:00"))
    except ValueError:
        raise Rejected(400, f"{name} must be an ISO date or date and time, got {params[name]!r}") from None
    return (parsed.replace(tzinfo=UTC) if parsed.tzinfo is None else parsed).timestamp()


def _number(params: Mapping[str, str], name: str, kind: type[Any], low: float, high: float) -> Any:
    try:
        value = kind(params[name])
    except ValueError:
        raise Rejected(
            400, f"{name} must be {'an integer' if kind is int else 'a number'}, got {params[name]!r}"
        ) from None
    if not low <= value <= high or (kind is float and not math.isfinite(value)):
        raise Rejected(400, f"{name} must be within {low:g}..{high:g}, got {params[name]!r}")
    return value
