"""Counting exceptions against limits: "3 MoveErrors from the telescope within 10 min" escalates.

Pure bookkeeping with times passed in; the module decides what escalation means (by default: go
to error state).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

from nightcrew.errors import NightcrewError

__all__ = ["ErrorLimit", "ErrorLimits"]

#: Called with the exception that hit the limit.
Escalation = Callable[[BaseException], None]


@dataclass
class ErrorLimit:
    """One registered limit.

    Attributes:
        error_type: Counted exception class (subclasses count too).
        limit: Number of occurrences that escalates.
        timespan: Only occurrences within this many seconds count; None: all since the last reset.
        module: Only count errors that came from this remote module; None: any origin.
        callback: What to do when the limit is hit; None: the owner's default.
    """

    error_type: type[BaseException]
    limit: int
    timespan: float | None = None
    module: str | None = None
    callback: Escalation | None = None
    times: deque[float] = field(default_factory=deque)

    def matches(self, exc: BaseException) -> bool:
        if not isinstance(exc, self.error_type):
            return False
        return self.module is None or (isinstance(exc, NightcrewError) and exc.module == self.module)


class ErrorLimits:
    """The limits of one module."""

    def __init__(self) -> None:
        self._limits: list[ErrorLimit] = []

    def register(self, limit: ErrorLimit) -> None:
        if limit.limit < 1:
            raise ValueError(f"error limit must be >= 1, got {limit.limit}")
        self._limits.append(limit)

    def record(self, exc: BaseException, now: float) -> list[ErrorLimit]:
        """Count ``exc`` at time ``now``; return the limits it made hit (their counts restart)."""
        hit = []
        for limit in self._limits:
            if not limit.matches(exc):
                continue
            limit.times.append(now)
            if limit.timespan is not None:
                while limit.times and limit.times[0] < now - limit.timespan:
                    limit.times.popleft()
            if len(limit.times) >= limit.limit:
                limit.times.clear()
                hit.append(limit)
        return hit

    def reset(self) -> None:
        for limit in self._limits:
            limit.times.clear()
