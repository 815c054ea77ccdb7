"""Roof movements others must know about (a closing roof means: stop observing)."""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.events.base import Event

__all__ = ["RoofClosedEvent", "RoofClosingEvent", "RoofOpenedEvent"]


@dataclass(frozen=True, kw_only=True)
class RoofOpenedEvent(Event):
    """The roof is fully open."""

    persistent = True


@dataclass(frozen=True, kw_only=True)
class RoofClosingEvent(Event):
    """The roof started closing."""

    persistent = True


@dataclass(frozen=True, kw_only=True)
class RoofClosedEvent(Event):
    """The roof is fully closed."""

    persistent = True
