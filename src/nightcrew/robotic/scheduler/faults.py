"""Device faults under a task: plan it again later, with a back-off, up to a limit.

A task that failed because a device failed (a camera module restarted mid-exposure, a mount that
lost its server) is not at fault itself: it should run again the same night, but not at once (the
device may still be coming back) and not forever (a device that keeps failing wastes the night).
:class:`DeviceFaults` counts the faults of each task and holds its block back: the block may start
no earlier than ``backoff_s`` after the fault, doubled for each further fault of that task, and
after ``limit`` faults it is given up for the night; the next night starts the count afresh. Pure:
the caller passes the times.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from datetime import datetime, timedelta

from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.scheduler.blocks import Night, SchedulableBlock

__all__ = ["DeviceFaults"]


class DeviceFaults:
    """Device faults per task and when each task may run again.

    Args:
        backoff_s: Seconds after the first fault before the task may start again; doubled per fault.
        limit: Faults after which the task is given up (:meth:`record` returns None).
    """

    def __init__(self, *, backoff_s: float = 300.0, limit: int = 3) -> None:
        if not backoff_s >= 0:
            raise InvalidArgumentError(f"device_fault_backoff_s must be >= 0, got {backoff_s}")
        if not limit >= 1:
            raise InvalidArgumentError(f"max_device_faults must be >= 1, got {limit}")
        self.backoff_s = backoff_s
        self.limit = limit
        self.counts: dict[str, int] = {}
        #: Task id → the earliest time it may start again.
        self.retry_at: dict[str, datetime] = {}
        self._night_end: datetime | None = None

    def start_night(self, night_end: datetime) -> None:
        """Forget every fault when the night ending at ``night_end`` is another than the last one's
        (the ends of one night, planned at different times, differ by seconds, not hours)."""
        if self._night_end is not None and abs((night_end - self._night_end).total_seconds()) > 3600:
            self.counts.clear()
            self.retry_at.clear()
        self._night_end = night_end

    def record(self, task_id: str, now: datetime) -> datetime | None:
        """Count a fault of ``task_id`` at ``now``: when it may run again, or None when given up."""
        count = self.counts.get(task_id, 0) + 1
        self.counts[task_id] = count
        if count >= self.limit:
            self.retry_at.pop(task_id, None)
            return None
        retry_at = now + timedelta(seconds=self.backoff_s * 2 ** (count - 1))
        self.retry_at[task_id] = retry_at
        return retry_at

    def hold_back(self, blocks: Sequence[SchedulableBlock], night: Night) -> list[SchedulableBlock]:
        """``blocks`` with the windows of those held back cut to start at their retry time."""
        return [self._held(block, night) if block.id in self.retry_at else block for block in blocks]

    def _held(self, block: SchedulableBlock, night: Night) -> SchedulableBlock:
        earliest = self.retry_at[block.id]
        windows = block.windows or ((night.start, night.end),)
        cut = tuple((max(start, earliest), end) for start, end in windows if end > earliest)
        # No window left after the back-off: keep one that ended, so the block stays (and is
        # explained as outside the night) rather than vanishing without a reason.
        return dataclasses.replace(block, windows=cut or ((earliest, earliest + timedelta(seconds=1)),))
