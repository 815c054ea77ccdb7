"""The safety watchdog's verdict: roofs close and telescopes park by themselves on an alarm."""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.events.base import Event

__all__ = ["SafetyAlarmEvent", "SafetyClearedEvent"]


@dataclass(frozen=True, kw_only=True)
class SafetyAlarmEvent(Event):
    """A module that keeps the observatory safe went silent or into error: close, park, stay closed."""

    persistent = True
    moves_hardware = True

    reason: str = ""  # which modules, since when, for a person


@dataclass(frozen=True, kw_only=True)
class SafetyClearedEvent(Event):
    """Every safety heartbeat is back and the weather is good: the roof may open again."""

    persistent = True
    moves_hardware = True
