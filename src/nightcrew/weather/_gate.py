"""When to declare the weather good or bad: bad at once, good only after a minimum good time.

The gate sees the combined verdict of all checks at every evaluation and says when the declared
weather changes. It starts with nothing declared: the first verdict, if bad, is declared bad at
once; a good verdict, first or later, must hold for ``min_good_time`` seconds before it is declared
good (fail safe: a starting observatory waits like one coming out of rain).
"""

from __future__ import annotations

from enum import Enum

__all__ = ["GoodWeatherGate", "WeatherChange"]


class WeatherChange(Enum):
    """A change of the declared weather."""

    BAD = "bad"
    GOOD = "good"


class GoodWeatherGate:
    """Turns a stream of (good?, time) verdicts into declared changes.

    Args:
        min_good_time: Seconds the verdict must stay good before good weather is declared, >= 0.
    """

    def __init__(self, min_good_time: float) -> None:
        if not min_good_time >= 0:
            raise ValueError(f"min_good_time must be >= 0 seconds, got {min_good_time}")
        self.min_good_time = float(min_good_time)
        self.declared_good: bool | None = None  # None: nothing declared yet
        self._good_since: float | None = None

    @property
    def is_good(self) -> bool:
        """Whether good weather has been declared (and not revoked)."""
        return self.declared_good is True

    @property
    def eta(self) -> float | None:
        """When good weather will be declared if the verdict stays good; None if it is not good."""
        return None if self._good_since is None else self._good_since + self.min_good_time

    def update(self, good: bool, now: float) -> WeatherChange | None:
        """Feed the verdict at clock time ``now``; return the change to announce, if any."""
        if not good:
            self._good_since = None
            if self.declared_good is not False:
                self.declared_good = False
                return WeatherChange.BAD
            return None
        if self._good_since is None:
            self._good_since = now
        if self.declared_good is not True and now - self._good_since >= self.min_good_time:
            self.declared_good = True
            return WeatherChange.GOOD
        return None
