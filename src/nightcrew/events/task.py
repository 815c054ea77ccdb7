"""Progress of scheduled tasks run by the mastermind."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from nightcrew.events.base import Event

__all__ = ["TaskFailedEvent", "TaskFinishedEvent", "TaskStartedEvent"]


@dataclass(frozen=True, kw_only=True)
class TaskStartedEvent(Event):
    """A task started."""

    name: str
    id: str  # the task archive's id
    eta: datetime | None = None  # expected end, if known


@dataclass(frozen=True, kw_only=True)
class TaskFinishedEvent(Event):
    """A task ended as planned."""

    name: str
    id: str


@dataclass(frozen=True, kw_only=True)
class TaskFailedEvent(Event):
    """A task ended early."""

    name: str
    id: str
    reason: str  # for a person, e.g. the error message
    # True when the task was interrupted from outside (weather, roof, dawn, shutdown) and may run
    # again later; False when it failed by itself and should not be planned again tonight.
    retryable: bool = False
