"""Results of focus series."""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.events.base import Event

__all__ = ["FocusFailedEvent", "FocusFoundEvent"]


@dataclass(frozen=True, kw_only=True)
class FocusFoundEvent(Event):
    """A focus series found the best focus (e.g. for a focus model to learn from)."""

    focus: float  # mm
    error: float  # mm, uncertainty of focus
    filter_name: str | None = None  # filter the series was taken in, if any


@dataclass(frozen=True, kw_only=True)
class FocusFailedEvent(Event):
    """A focus series gave no best focus (e.g. no clear V); the focuser goes back where it was."""

    reason: str  # why, e.g. "the widths do not form a clear V"
    filter_name: str | None = None  # filter the series was taken in, if any
