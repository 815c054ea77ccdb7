"""Modules appearing, disappearing and changing state. The sender is the module concerned."""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.events.base import Event
from nightcrew.interfaces.enums import ModuleState

__all__ = ["ModuleClosedEvent", "ModuleOpenedEvent", "ModuleStateChangedEvent"]


# No fields: the comm synthesises these from presence, with the module as sender.
@dataclass(frozen=True, kw_only=True)
class ModuleOpenedEvent(Event):
    """A module came online."""


@dataclass(frozen=True, kw_only=True)
class ModuleClosedEvent(Event):
    """A module went offline."""


@dataclass(frozen=True, kw_only=True)
class ModuleStateChangedEvent(Event):
    """A module's lifecycle state changed."""

    persistent = True

    last: ModuleState
    current: ModuleState
    error: str = ""  # the error string when entering error state
