"""A check: one sensor of one station judged by its evaluators; the weather is good when all are.

Every check is at least a :class:`~nightcrew.weather.Valid` check: if none of its evaluators is one,
a ``Valid()`` (5 minutes) comes first, so stale data can never keep the roof open.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from nightcrew.weather._evaluators import Evaluator, Valid, Verdict
from nightcrew.weather._readings import Reading

__all__ = ["CheckResult", "SensorCheck"]


@dataclass(frozen=True)
class CheckResult:
    """The verdict of every evaluator of a check, in order."""

    verdicts: tuple[Verdict, ...]

    @property
    def good(self) -> bool:
        return all(v.good for v in self.verdicts)

    @property
    def reason(self) -> str:
        """Why the check failed ("" if it did not)."""
        return "; ".join(dict.fromkeys(v.reason for v in self.verdicts if not v.good))


class SensorCheck:
    """``sensor`` of ``station`` judged by ``evaluators`` (a Valid() is added unless present)."""

    def __init__(self, station: str, sensor: str, evaluators: Sequence[Evaluator]) -> None:
        self.station = station
        self.sensor = sensor
        has_valid = any(isinstance(e, Valid) for e in evaluators)
        self.evaluators: tuple[Evaluator, ...] = tuple(evaluators) if has_valid else (Valid(), *evaluators)

    @property
    def name(self) -> str:
        return f"{self.station}.{self.sensor}"

    def evaluate(self, reading: Reading | None, now: float, previous: CheckResult | None) -> CheckResult:
        """Run every evaluator, each seeing its own previous verdict (for hysteresis)."""
        before: Sequence[Verdict | None] = previous.verdicts if previous else [None] * len(self.evaluators)
        return CheckResult(
            tuple(e.evaluate(reading, now, p) for e, p in zip(self.evaluators, before, strict=True))
        )
