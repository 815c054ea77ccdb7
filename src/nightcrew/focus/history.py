"""The focus model's memory: measured best focus with the temperatures at that time.

Records travel to and from plain mappings (one YAML list entry each) so the module can keep them in
a VFS file across restarts. Reading is forgiving per record: a damaged entry is reported and
skipped, the rest still count.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from datetime import datetime
from typing import Any

__all__ = ["FocusRecord", "records_from_plain", "records_to_plain"]


@dataclass(frozen=True)
class FocusRecord:
    """One best focus found by a focus series.

    Attributes:
        time: When it was found (aware datetime, UTC).
        focus: Best focus in mm.
        error: Its one-sigma uncertainty in mm.
        filter_name: Filter of the series, if any.
        temperatures: Model variable → value (°C) read when the focus was found.
    """

    time: datetime
    focus: float
    error: float
    filter_name: str | None = None
    temperatures: dict[str, float] = field(default_factory=dict)

    def to_plain(self) -> dict[str, Any]:
        return {
            "time": self.time.isoformat(),
            "focus": self.focus,
            "error": self.error,
            "filter": self.filter_name,
            "temperatures": dict(self.temperatures),
        }

    @classmethod
    def from_plain(cls, entry: Mapping[str, Any]) -> FocusRecord:
        """A record from :meth:`to_plain`'s form; ValueError/TypeError/KeyError if damaged."""
        time = datetime.fromisoformat(str(entry["time"]))
        focus, error = float(entry["focus"]), float(entry["error"])
        temperatures = {str(k): float(v) for k, v in dict(entry.get("temperatures") or {}).items()}
        values = [focus, error, *temperatures.values()]
        if not all(math.isfinite(v) for v in values):
            raise ValueError("non-finite value")
        name = entry.get("filter")
        return cls(time, focus, error, None if name is None else str(name), temperatures)


def records_to_plain(records: Iterable[FocusRecord]) -> list[dict[str, Any]]:
    return [record.to_plain() for record in records]


def records_from_plain(entries: Any) -> tuple[list[FocusRecord], list[str]]:
    """Records from a loaded YAML value, plus one problem text per skipped entry."""
    if entries is None:
        return [], []
    if not isinstance(entries, list):
        return [], [f"expected a list of records, got {type(entries).__name__}"]
    records: list[FocusRecord] = []
    problems: list[str] = []
    for index, entry in enumerate(entries):
        try:
            if not isinstance(entry, Mapping):
                raise TypeError(f"expected a mapping, got {type(entry).__name__}")
            records.append(FocusRecord.from_plain(entry))
        except (KeyError, TypeError, ValueError) as exc:
            problems.append(f"record {index}: {type(exc).__name__}: {exc}")
    return records, problems
