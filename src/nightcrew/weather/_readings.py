"""Readings and the two special stations that combine several: Current (latest) and Average (mean).

A reading is a value with the clock time (Unix seconds) it was measured. ``None`` as a value means
the sensor answered without a value; a missing reading (``None`` instead of a :class:`Reading`)
means the station did not answer at all. Both count as bad weather downstream.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

__all__ = ["Reading", "average_reading", "latest_reading"]


@dataclass(frozen=True)
class Reading:
    """One measurement: ``value`` (None when the sensor had none) taken at clock time ``time``."""

    time: float
    value: float | None

    def age(self, now: float) -> float:
        """Seconds since the measurement (negative for a reading from the future)."""
        return now - self.time


def _usable(reading: Reading | None) -> bool:
    return reading is not None and reading.value is not None and math.isfinite(reading.value)


def latest_reading(readings: Sequence[Reading | None]) -> Reading | None:
    """The newest reading that has a value (the Current station); None if there is none."""
    usable = [r for r in readings if r is not None and _usable(r)]
    return max(usable, key=lambda r: r.time, default=None)


def average_reading(readings: Sequence[Reading | None], now: float, max_age: float) -> Reading | None:
    """The mean of the readings with a value at most ``max_age`` old (the Average station).

    Its time is that of the oldest reading used, so a mean is never fresher than its inputs.
    None when no reading qualifies.
    """
    fresh = [r for r in readings if r is not None and _usable(r) and r.age(now) <= max_age]
    if not fresh:
        return None
    values = [r.value for r in fresh if r.value is not None]
    return Reading(time=min(r.time for r in fresh), value=sum(values) / len(values))
