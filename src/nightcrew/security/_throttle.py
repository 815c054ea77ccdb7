"""A brake on repeated warnings: one line per key (a sender and what it sent) per period.

A room member forging events could otherwise write a log line per forged event, as fast as the
server relays them. The first refusal is logged at once; the next ones within the period are
counted and the count is told with the next line that is logged.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Hashable

__all__ = ["WarningThrottle"]

_MAX_KEYS = 10_000  # many senders: forget those quiet for a period


class WarningThrottle:
    """Whether a warning for ``key`` is due now (at most one per ``period`` wall seconds)."""

    def __init__(self, period: float = 60.0, *, now: Callable[[], float] = time.monotonic) -> None:
        self._period = period
        self._now = now
        self._last: dict[Hashable, tuple[float, int]] = {}  # key -> (time logged, held back since)

    def due(self, key: Hashable) -> int | None:
        """The number of warnings held back since the last one for ``key`` if one is due now;
        None to hold this one back too."""
        now = self._now()
        if len(self._last) > _MAX_KEYS:
            self._last = {k: v for k, v in self._last.items() if now - v[0] < self._period}
        logged = self._last.get(key)
        if logged is not None and now - logged[0] < self._period:
            self._last[key] = (logged[0], logged[1] + 1)
            return None
        self._last[key] = (now, 0)
        return logged[1] if logged is not None else 0
