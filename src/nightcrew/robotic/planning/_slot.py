"""The planned slot: task ``task_id`` from ``start`` to ``end``."""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from nightcrew.errors import InvalidArgumentError

__all__ = ["PlannedSlot"]


@dataclass(frozen=True)
class PlannedSlot:
    """Task ``task_id`` is planned from ``start`` to ``end`` (aware datetimes).

    ``start`` is when the telescope begins with it (slew and set-up first), ``end`` when its
    observation ends; the task is not started at or after ``end``.
    """

    task_id: str
    start: datetime
    end: datetime

    def __post_init__(self) -> None:
        if self.start.utcoffset() is None or self.end.utcoffset() is None:
            raise InvalidArgumentError(f"planned slot of task {self.task_id}: start and end need a time zone")
        if self.end <= self.start:
            raise InvalidArgumentError(
                f"planned slot of task {self.task_id}: end {self.end} is not after its start {self.start}"
            )
