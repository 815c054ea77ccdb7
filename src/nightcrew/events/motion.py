"""Status changes of moving devices (telescopes, roofs, focusers, filter wheels)."""

from __future__ import annotations

from dataclasses import dataclass, field

from nightcrew.events.base import Event
from nightcrew.interfaces.enums import MotionStatus

__all__ = ["FilterChangedEvent", "MotionStatusChangedEvent"]


@dataclass(frozen=True, kw_only=True)
class MotionStatusChangedEvent(Event):
    """The motion status of a module, or of one of its devices, changed."""

    persistent = True

    status: MotionStatus  # of the module as a whole
    #: Device name → its status, for modules driving several devices (see IMotion).
    devices: dict[str, MotionStatus] = field(default_factory=dict)


@dataclass(frozen=True, kw_only=True)
class FilterChangedEvent(Event):
    """A filter wheel moved a new filter into the beam."""

    persistent = True

    filter_name: str
