"""The base of all events.

An event is a frozen dataclass of wire-encodable fields (see :mod:`nightcrew.comm.codec`). Every
event class registers itself by class name, which is also its name on the wire, so a receiver can
rebuild it (:func:`event_by_name`). On the wire an event is a JSON object of its fields.

An event on which receivers close, open, park or clear an alarm sets ``moves_hardware``: comms
trust it only from the senders the access policy names for it (docs/security.md), so a new such
event cannot be forgotten by the policy.
"""

from __future__ import annotations

import dataclasses
from typing import Any, ClassVar, Self

__all__ = ["Event", "event_by_name", "event_names", "hardware_event_names"]

_EVENTS: dict[str, type[Event]] = {}


@dataclasses.dataclass(frozen=True, kw_only=True)
class Event:
    """Base class of all events. Subclasses are frozen, keyword-only dataclasses."""

    #: Whether the event reports a state that holds until the next one of its kind from the same
    #: sender (the catalogue's ``x-persistent``, docs/protocol.md section 5); routing ignores it.
    persistent: ClassVar[bool] = False
    #: Whether receivers move hardware on it (close, open, park, clear an alarm): trusted only from
    #: the senders the access policy names for it, refused from everyone else.
    moves_hardware: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if cls.__name__ in _EVENTS and _EVENTS[cls.__name__].__module__ != cls.__module__:
            raise TypeError(f"event name {cls.__name__} is already taken")
        _EVENTS[cls.__name__] = cls

    @classmethod
    def event_name(cls) -> str:
        """The event's name on the wire."""
        return cls.__name__

    def to_dict(self) -> dict[str, Any]:
        """The event's fields as wire values."""
        from nightcrew.comm.codec import encode

        return {f.name: encode(getattr(self, f.name)) for f in dataclasses.fields(self)}

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Self:
        """Rebuild the event from wire values; unknown fields are ignored (newer senders)."""
        from nightcrew.comm.codec import decode_fields

        return cls(**decode_fields(cls, data))


def event_names() -> list[str]:
    """Names of all event classes this process knows, sorted."""
    return sorted(_EVENTS)


def event_by_name(name: str) -> type[Event] | None:
    """The event class called ``name``, or None if this process does not know it."""
    return _EVENTS.get(name)


def hardware_event_names() -> list[str]:
    """Names of the event classes that move hardware (``moves_hardware``), sorted."""
    return sorted(name for name, event in _EVENTS.items() if event.moves_hardware)
