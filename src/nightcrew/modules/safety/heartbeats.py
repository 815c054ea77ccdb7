"""Which watched modules are overdue: pure bookkeeping of the last good answer of each (no I/O).

A module's heartbeat is good when it answered and was READY; anything else (no answer, an error
state, offline) is a missed beat with a reason. A module is overdue once its last good beat lies
more than its limit in the past; at the start every module counts as good once, so it gets its
whole limit to show up.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["HeartbeatMonitor"]


@dataclass
class HeartbeatMonitor:
    """Last good beat and last problem of every watched module (times in clock seconds)."""

    limits: dict[str, float]
    start: float
    _last_good: dict[str, float] = field(default_factory=dict, init=False)
    _problem: dict[str, str] = field(default_factory=dict, init=False)

    def __post_init__(self) -> None:
        for name, limit in self.limits.items():
            if not limit > 0:
                raise ValueError(f"the limit of '{name}' must be > 0 seconds, got {limit}")
        self._last_good = dict.fromkeys(self.limits, self.start)

    def beat(self, name: str, now: float, problem: str | None = None) -> None:
        """Record ``name``'s answer at ``now``: good without ``problem``, else a missed beat."""
        if problem is None:
            self._last_good[name] = now
            self._problem.pop(name, None)
        else:
            self._problem[name] = problem

    def overdue(self, now: float) -> dict[str, str]:
        """Module → why it is overdue (its problem and for how long), for every overdue module."""
        late = {}
        for name, limit in self.limits.items():
            silent = now - self._last_good[name]
            if silent > limit:
                problem = self._problem.get(name, "no answer")
                late[name] = f"{name}: {problem} for {silent:.0f} s (limit {limit:g} s)"
        return late
