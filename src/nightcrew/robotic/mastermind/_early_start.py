"""Whether the next task may start before its slot: observable from now on, computed once per slot."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from datetime import datetime, timedelta

from nightcrew.robotic.mastermind._decide import Slot
from nightcrew.robotic.mastermind._tasks import observable_since, window_begun
from nightcrew.robotic.tasks import Request, Task
from nightcrew.site import Site

__all__ = ["EarlyStarts"]


class EarlyStarts:
    """Marks the next slot ``startable_now`` when its task may start up to ``early_start`` early.

    Since when a task is observable before its slot needs a small sky grid (from the first time it
    is asked until the slot); the mastermind asks at every step while it waits, so the answer is
    kept per (task, slot start) and holds for every later step - a new plan or a changed request
    computes it again.

    Args:
        site: Where the observatory is.
        early_start: How long before its slot a task may start; zero: never early.
    """

    def __init__(self, site: Site, early_start: timedelta) -> None:
        self._site, self.early_start = site, early_start
        self._since: dict[tuple[str, datetime], tuple[Request, datetime | None]] = {}

    def mark(self, slots: Sequence[Slot], tasks: Mapping[str, Task], now: datetime) -> list[Slot]:
        """``slots`` with the next one marked startable now if nothing is due and its task may start."""
        if not self.early_start or any(s.is_due(now) and s.may_run for s in slots):
            return list(slots)
        upcoming = [s for s in slots if s.may_run and now < s.start <= now + self.early_start]
        if not upcoming:
            return list(slots)
        first = min(upcoming, key=lambda s: s.start)
        if not self._startable(tasks[first.task_id], first.start, now):
            return list(slots)
        return [replace(s, startable_now=True) if s is first else s for s in slots]

    def _startable(self, task: Task, start: datetime, now: datetime) -> bool:
        request = task.request
        if not window_begun(request, now, start):
            return False
        key = (task.id, start)
        known = self._since.get(key)
        if known is None or known[0] != request:
            # Slots that have begun are no longer asked about: keep only those still ahead.
            self._since = {k: v for k, v in self._since.items() if k[1] > now}
            known = (request, observable_since(request, self._site, start, lookback=start - now))
            self._since[key] = known
        since = known[1]
        return since is not None and since <= now
