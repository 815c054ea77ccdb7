"""The safety watchdog's verdict: roofs close and telescopes park by themselves on an alarm."""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.events.base import Event

__all__ = ["SafetyAlarmEvent", "SafetyClearedEvent", "WatchdogHeartbeatEvent"]


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


@dataclass(frozen=True, kw_only=True)
class WatchdogHeartbeatEvent(Event):
    """The safety watchdog is alive and watching (sent every round): the dead-man's switch of roofs
    and telescopes that name it releases when these stop (nightcrew.modules.motion.base). Trusted
    only from its senders, since a forged one would hold a roof open under a frozen watchdog."""

    moves_hardware = True
