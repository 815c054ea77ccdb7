"""An event with no meaning, for checking that events arrive."""

from __future__ import annotations

from dataclasses import dataclass

from nightcrew.events.base import Event

__all__ = ["TestEvent"]


@dataclass(frozen=True, kw_only=True)
class TestEvent(Event):
    """Sent by tests and by ``nightcrew`` diagnostics."""

    __test__ = False  # not a pytest test class, despite its name

    message: str = ""
