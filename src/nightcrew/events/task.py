"""Progress of scheduled tasks run by the mastermind."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import ClassVar

from nightcrew.events.base import Event

__all__ = [
    "RapidResponseEvent",
    "ScheduleChangedEvent",
    "TaskFailedEvent",
    "TaskFinishedEvent",
    "TaskStartedEvent",
    "TasksChangedEvent",
]


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
    # True when a device (camera, mount, ...) failed under the task, not the task's own content: the
    # scheduler retries it later the same night with a back-off instead of dropping it.
    device_fault: bool = False


@dataclass(frozen=True, kw_only=True)
class TasksChangedEvent(Event):
    """Tasks were added to, changed in or withdrawn from a task archive: planners look again now
    instead of at their next poll."""

    ids: tuple[str, ...]  # the archive's ids of the tasks concerned
    change: str  # "added", "changed" or "cancelled"


@dataclass(frozen=True, kw_only=True)
class ScheduleChangedEvent(Event):
    """The scheduler wrote a new schedule: whoever runs it reads it now instead of at the next poll
    (a task that ended before its slot leaves no idle gap until then)."""

    ids: tuple[str, ...]  # the archive's ids of the planned tasks, in the order of their slots


@dataclass(frozen=True, kw_only=True)
class RapidResponseEvent(Event):
    """Rapid-response tasks were submitted: a mastermind stops a running task of lower priority for
    them (its frame in flight kept) and runs them at once. It moves the telescope off its task, so
    it is trusted only from the senders the access policy names for it (docs/rapid-response.md)."""

    moves_hardware: ClassVar[bool] = True

    ids: tuple[str, ...]  # the archive's ids of the rapid-response tasks
