"""What a person reads for an event: one line, or None for an event not worth a message."""

from __future__ import annotations

import dataclasses

from nightcrew.events import (
    BadWeatherEvent,
    Event,
    ModuleStateChangedEvent,
    RoofClosedEvent,
    SafetyAlarmEvent,
    TaskFailedEvent,
)
from nightcrew.interfaces import ModuleState

__all__ = ["describe_event"]


def describe_event(event: Event, sender: str) -> str | None:
    """One line for ``event`` from ``sender``; None for a state change that is not an error."""
    if isinstance(event, BadWeatherEvent):
        return f"BAD WEATHER ({sender}): {event.reason or 'no reason given'}"
    if isinstance(event, RoofClosedEvent):
        return f"Roof closed ({sender})"
    if isinstance(event, TaskFailedEvent):
        return f"TASK FAILED ({sender}): {event.name} [{event.id}]: {event.reason}"
    if isinstance(event, SafetyAlarmEvent):
        return f"SAFETY ALARM ({sender}): {event.reason or 'no reason given'}"
    if isinstance(event, ModuleStateChangedEvent):
        if event.current is not ModuleState.ERROR:
            return None
        return f"MODULE ERROR: {sender}: {event.error or 'no message'}"
    fields = ", ".join(f"{f.name}={getattr(event, f.name)!r}" for f in dataclasses.fields(event))
    return f"{event.event_name()} ({sender}){': ' + fields if fields else ''}"
