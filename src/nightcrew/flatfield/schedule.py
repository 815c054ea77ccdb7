"""Which flats to take next: several filter/binning combinations, the longest-waiting first.

Each combination's priority is its weight times the hours since it was last taken (never taken:
first of all, in configuration order). The state — when each was last taken — is plain data that
the scheduler module keeps in a VFS file.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.flatfield.exptime import binning_key, parse_binning

__all__ = ["FlatTask", "last_taken_from_plain", "prioritised", "tasks_from_config"]

_KEYS = {"filter", "binning", "count", "weight"}


@dataclass(frozen=True)
class FlatTask:
    """One combination to take: ``count`` flats in ``filter_name`` at ``binning``."""

    filter_name: str | None
    binning: tuple[int, int]
    count: int
    weight: float = 1.0

    @property
    def key(self) -> str:
        """Name of the combination in the persisted state, e.g. ``V 2x2``."""
        return f"{self.filter_name or 'none'} {binning_key(*self.binning)}"


def tasks_from_config(entries: Sequence[Mapping[str, Any]], key: str = "flats") -> list[FlatTask]:
    """Tasks from ``[{filter: V, binning: 2x2, count: 10, weight: 1}, ...]``; ConfigError naming the entry."""
    if not entries:
        raise ConfigError("needs at least one {filter, binning, count} entry", key=key)
    tasks: list[FlatTask] = []
    for index, entry in enumerate(entries):
        where = f"{key}[{index}]"
        if not isinstance(entry, Mapping):
            raise ConfigError(f"expected a mapping, got {entry!r}", key=where)
        unknown = sorted(set(entry) - _KEYS)
        if unknown:
            raise ConfigError(f"unknown keys {unknown}; known: {', '.join(sorted(_KEYS))}", key=where)
        try:
            binning = parse_binning(str(entry.get("binning", "1x1")))
        except ValueError as exc:
            raise ConfigError(str(exc), key=f"{where}.binning") from None
        count, weight = entry.get("count", 10), entry.get("weight", 1.0)
        if not isinstance(count, int) or isinstance(count, bool) or count < 1:
            raise ConfigError(f"must be a whole number >= 1, got {count!r}", key=f"{where}.count")
        if not isinstance(weight, int | float) or not weight > 0:
            raise ConfigError(f"must be a number > 0, got {weight!r}", key=f"{where}.weight")
        name = entry.get("filter")
        task = FlatTask(None if name is None else str(name), binning, count, float(weight))
        if any(t.key == task.key for t in tasks):
            raise ConfigError(f"{task.key} is listed twice", key=where)
        tasks.append(task)
    return tasks


def prioritised(
    tasks: Sequence[FlatTask], last_taken: Mapping[str, datetime], now: datetime
) -> list[FlatTask]:
    """``tasks`` by falling priority (never taken first, then weight * hours since last taken)."""

    def priority(task: FlatTask) -> float:
        when = last_taken.get(task.key)
        if when is None:
            return math.inf
        return task.weight * max(0.0, (now - when).total_seconds() / 3600.0)

    order = {task.key: index for index, task in enumerate(tasks)}
    return sorted(tasks, key=lambda t: (-priority(t), order[t.key]))


def last_taken_from_plain(value: Any) -> tuple[dict[str, datetime], list[str]]:
    """The persisted state ``{key: ISO time}``, plus one problem text per skipped entry."""
    if value is None:
        return {}, []
    if not isinstance(value, Mapping):
        return {}, [f"expected a mapping of combination to time, got {type(value).__name__}"]
    state: dict[str, datetime] = {}
    problems: list[str] = []
    for name, when in value.items():
        try:
            parsed = when if isinstance(when, datetime) else datetime.fromisoformat(str(when))
        except ValueError as exc:
            problems.append(f"{name}: {exc}")
            continue
        if parsed.tzinfo is None:
            problems.append(f"{name}: time {when!r} has no time zone")
            continue
        state[str(name)] = parsed
    return state, problems
