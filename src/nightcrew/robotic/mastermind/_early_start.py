"""When the next task may start before its slot: observable from then on, computed once per slot."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import replace
from datetime import datetime, timedelta

from nightcrew.robotic.mastermind._decide import Slot
from nightcrew.robotic.mastermind._tasks import startable_from
from nightcrew.robotic.tasks import Request, Task
from nightcrew.site import Site

__all__ = ["EarlyStarts"]


class EarlyStarts:
    """Marks when the next slot's task may start up to ``early_start`` early, and if it may now.

    The next slot, once it starts within ``early_start`` + ``keep_open``, gets ``early_from`` (when
    it becomes startable, :func:`startable_from`) - so :func:`decide` keeps the roof open for it -
    and ``startable_now`` from then on. That needs a small sky grid over ``early_start`` before the
    slot; the mastermind asks at every step while it waits, so the answer is kept per (task, slot
    start) - a new plan or a changed request computes it again.

    Args:
        site: Where the observatory is.
        early_start: How long before its slot a task may start; zero: never early.
        keep_open: How long before it may start early the next slot is marked (``early_from``).
    """

    def __init__(self, site: Site, early_start: timedelta, *, keep_open: timedelta = timedelta(0)) -> None:
        self._site, self.early_start, self._keep_open = site, early_start, keep_open
        self._from: dict[tuple[str, datetime], tuple[Request, datetime | None]] = {}

    def mark(self, slots: Sequence[Slot], tasks: Mapping[str, Task], now: datetime) -> list[Slot]:
        """``slots`` with the next one marked if nothing is due and its task may start early."""
        if not self.early_start or any(s.is_due(now) and s.may_run for s in slots):
            return list(slots)
        reach = now + self.early_start + self._keep_open
        upcoming = [s for s in slots if s.may_run and now < s.start <= reach]
        if not upcoming:
            return list(slots)
        first = min(upcoming, key=lambda s: s.start)
        since = self._early_from(tasks[first.task_id], first.start, now)
        if since is None:
            return list(slots)
        marked = replace(first, early_from=since, startable_now=since <= now)
        return [marked if s is first else s for s in slots]

    def _early_from(self, task: Task, start: datetime, now: datetime) -> datetime | None:
        key = (task.id, start)
        known = self._from.get(key)
        if known is None or known[0] != task.request:
            # Slots that have begun are no longer asked about: keep only those still ahead.
            self._from = {k: v for k, v in self._from.items() if k[1] > now}
            known = (task.request, startable_from(task.request, self._site, start, lookback=self.early_start))
            self._from[key] = known
        return known[1]
