"""Evaluators: is one sensor's reading good for observing? Pure functions of their inputs.

Every evaluator answers ``evaluate(reading, now, previous)`` with a :class:`Verdict`. ``previous`` is
the check's last verdict (None at the start); only :class:`Schmitt` uses it, for hysteresis. A
missing reading or one without a value is always bad (fail safe).

- :class:`Boolean` — good when the value, read as a flag (non-zero = true), equals ``good_when``.
- :class:`Switch` — one threshold: bad above ``bad_above`` or below ``bad_below``.
- :class:`Schmitt` — two thresholds: turns bad beyond the bad one, good again only past the good
  one; in between it keeps its last verdict (bad at the start), so a value hovering near a limit
  does not open and close the roof every minute.
- :class:`Valid` — bad when the reading is older than ``max_age`` seconds (default 5 min).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

from nightcrew.errors import ConfigError
from nightcrew.weather._readings import Reading

__all__ = ["DEFAULT_MAX_AGE", "Boolean", "Evaluator", "Schmitt", "Switch", "Valid", "Verdict"]

#: Readings older than this (seconds) are stale, unless a check sets its own Valid evaluator.
DEFAULT_MAX_AGE = 300.0


@dataclass(frozen=True)
class Verdict:
    """Whether a reading is good, and why not (for a person)."""

    good: bool
    reason: str = ""


_NO_VALUE = Verdict(False, "no value")


def _value_of(reading: Reading | None) -> float | None:
    return None if reading is None else reading.value


class Evaluator(ABC):
    """Judges one sensor's reading; subclasses are immutable and hold only their thresholds."""

    @abstractmethod
    def evaluate(self, reading: Reading | None, now: float, previous: Verdict | None = None) -> Verdict:
        """The verdict on ``reading`` at clock time ``now``, given the check's ``previous`` verdict."""


class Boolean(Evaluator):
    """Good when the value read as a flag equals ``good_when`` (a rain sensor: ``good_when: false``)."""

    def __init__(self, *, good_when: bool = False) -> None:
        self.good_when = bool(good_when)

    def evaluate(self, reading: Reading | None, now: float, previous: Verdict | None = None) -> Verdict:
        value = _value_of(reading)
        if value is None:
            return _NO_VALUE
        flag = value != 0.0
        return Verdict(True) if flag is self.good_when else Verdict(False, f"is {str(flag).lower()}")


def _one_side(bad_above: float | None, bad_below: float | None) -> None:
    if (bad_above is None) == (bad_below is None):
        raise ConfigError("give exactly one of bad_above and bad_below", key="bad_above")


class Switch(Evaluator):
    """Bad when the value is at or above ``bad_above`` (or at or below ``bad_below``): one threshold."""

    def __init__(self, *, bad_above: float | None = None, bad_below: float | None = None) -> None:
        _one_side(bad_above, bad_below)
        self.bad_above = bad_above
        self.bad_below = bad_below

    def evaluate(self, reading: Reading | None, now: float, previous: Verdict | None = None) -> Verdict:
        value = _value_of(reading)
        if value is None:
            return _NO_VALUE
        if self.bad_above is not None and value >= self.bad_above:
            return Verdict(False, f"{value:g} >= {self.bad_above:g}")
        if self.bad_below is not None and value <= self.bad_below:
            return Verdict(False, f"{value:g} <= {self.bad_below:g}")
        return Verdict(True)


class Schmitt(Evaluator):
    """A switch with hysteresis: bad at ``bad_above``, good again only below ``good_below``.

    Mirrored for lower limits: bad at ``bad_below``, good again only above ``good_above``.
    Between the two thresholds the previous verdict stands; without one it is bad.
    """

    def __init__(
        self,
        *,
        bad_above: float | None = None,
        good_below: float | None = None,
        bad_below: float | None = None,
        good_above: float | None = None,
    ) -> None:
        _one_side(bad_above, bad_below)
        if bad_above is not None:
            if good_below is None or good_above is not None:
                raise ConfigError("with bad_above, give good_below (and not good_above)", key="good_below")
            if not good_below <= bad_above:
                raise ConfigError(f"must be <= bad_above ({bad_above:g})", key="good_below")
        if bad_below is not None:
            if good_above is None or good_below is not None:
                raise ConfigError("with bad_below, give good_above (and not good_below)", key="good_above")
            if not good_above >= bad_below:
                raise ConfigError(f"must be >= bad_below ({bad_below:g})", key="good_above")
        self.bad_above, self.good_below = bad_above, good_below
        self.bad_below, self.good_above = bad_below, good_above

    def evaluate(self, reading: Reading | None, now: float, previous: Verdict | None = None) -> Verdict:
        value = _value_of(reading)
        if value is None:
            return _NO_VALUE
        if self.bad_above is not None and self.good_below is not None:
            if value >= self.bad_above:
                return Verdict(False, f"{value:g} >= {self.bad_above:g}")
            if value < self.good_below:
                return Verdict(True)
            limit = f"not yet below {self.good_below:g}"
        elif self.bad_below is not None and self.good_above is not None:
            if value <= self.bad_below:
                return Verdict(False, f"{value:g} <= {self.bad_below:g}")
            if value > self.good_above:
                return Verdict(True)
            limit = f"not yet above {self.good_above:g}"
        else:  # pragma: no cover - the constructor makes one pair complete
            raise AssertionError("Schmitt without thresholds")
        if previous is not None and previous.good:
            return previous
        return Verdict(False, f"{value:g} {limit}")


class Valid(Evaluator):
    """Bad when the reading is missing or older than ``max_age`` seconds (fail safe on stale data)."""

    def __init__(self, *, max_age: float = DEFAULT_MAX_AGE) -> None:
        if not max_age > 0:
            raise ConfigError(f"must be > 0 seconds, got {max_age}", key="max_age")
        self.max_age = float(max_age)

    def evaluate(self, reading: Reading | None, now: float, previous: Verdict | None = None) -> Verdict:
        if reading is None or reading.value is None:
            return _NO_VALUE
        age = reading.age(now)
        if age > self.max_age:
            return Verdict(False, f"stale ({age:.0f} s old)")
        return Verdict(True)
