"""The weather verdict changing; roofs and telescopes react to these by themselves."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from nightcrew.events.base import Event

__all__ = ["BadWeatherEvent", "GoodWeatherEvent"]


@dataclass(frozen=True, kw_only=True)
class GoodWeatherEvent(Event):
    """The weather became good."""

    persistent = True
    moves_hardware = True

    #: When the observatory may open (the weather module may demand a waiting period); None: now.
    eta: datetime | None = None


@dataclass(frozen=True, kw_only=True)
class BadWeatherEvent(Event):
    """The weather became bad: close and park now."""

    persistent = True
    moves_hardware = True

    reason: str = ""  # which sensors failed, for a person
