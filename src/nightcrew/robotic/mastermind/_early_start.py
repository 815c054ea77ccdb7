"""Whether the next task may start before its slot: observable from now until its slot begins."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from datetime import datetime, timedelta

from nightcrew.robotic.mastermind._decide import Slot
from nightcrew.robotic.mastermind._tasks import startable_now
from nightcrew.robotic.tasks import Task
from nightcrew.site import Site

__all__ = ["EarlyStarts"]


class EarlyStarts:
    """Marks the next slot ``startable_now`` when its task may start up to ``early_start`` early.

    Args:
        site: Where the observatory is.
        early_start: How long before its slot a task may start; zero: never early.
    """

    def __init__(self, site: Site, early_start: timedelta) -> None:
        self._site, self.early_start = site, early_start

    def mark(self, slots: Sequence[Slot], tasks: Mapping[str, Task], now: datetime) -> list[Slot]:
        """``slots`` with the next one marked startable now if nothing is due and its task may start."""
        if not self.early_start or any(s.is_due(now) and s.may_run for s in slots):
            return list(slots)
        upcoming = [s for s in slots if s.may_run and now < s.start <= now + self.early_start]
        if not upcoming:
            return list(slots)
        first = min(upcoming, key=lambda s: s.start)
        if not startable_now(tasks[first.task_id], self._site, now, first.start):
            return list(slots)
        return [replace(s, startable_now=True) if s is first else s for s in slots]
