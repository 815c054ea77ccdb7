"""When to restart a module that exited: exponential backoff and a limit (pure, no clock of its own).

A module that ran at least ``stable_after`` seconds counts as healthy again: its next crash is
restarted after ``first_delay``. Quick crashes in a row double the delay up to ``max_delay``;
more than ``max_restarts`` restarts within ``window`` seconds and the supervisor gives up on it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["RestartPolicy"]


@dataclass
class RestartPolicy:
    """Decides, from the start and exit times of one module, whether and when to restart it."""

    first_delay: float = 1.0
    max_delay: float = 60.0
    stable_after: float = 30.0
    max_restarts: int = 5
    window: float = 300.0
    _quick_failures: int = field(default=0, init=False)
    _restarts: list[float] = field(default_factory=list, init=False)

    def __post_init__(self) -> None:
        if not 0 < self.first_delay <= self.max_delay:
            raise ValueError(f"need 0 < first_delay <= max_delay, got {self.first_delay}, {self.max_delay}")
        if self.max_restarts < 0 or self.window <= 0 or self.stable_after < 0:
            raise ValueError("max_restarts must be >= 0, window > 0 and stable_after >= 0")

    def after_exit(self, started: float, exited: float) -> float | None:
        """Seconds to wait before the next start, or None when the limit is reached (give up)."""
        if exited - started >= self.stable_after:
            self._quick_failures = 0
        recent = [t for t in self._restarts if exited - t < self.window]
        if len(recent) >= self.max_restarts:
            self._restarts = recent
            return None
        delay = min(self.first_delay * 2.0**self._quick_failures, self.max_delay)
        self._quick_failures += 1
        self._restarts = [*recent, exited + delay]
        return delay

    def reset(self) -> None:
        """Forget past failures (an operator started the module by hand)."""
        self._quick_failures = 0
        self._restarts = []
