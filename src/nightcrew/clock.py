"""Clocks: every piece of nightcrew takes time from one of these, never from ``time`` directly.

A :class:`RealClock` follows the wall clock. An :class:`AcceleratedClock` starts at a chosen epoch
and runs ``speed`` times faster, so that a simulated night passes in minutes: ``sleep(60)`` on a
clock with speed 100 returns after 0.6 s of wall time, and ``now()`` has moved on by 60 s.
"""

from __future__ import annotations

import asyncio
import time
from abc import ABC, abstractmethod
from collections.abc import Callable
from datetime import UTC, datetime

__all__ = ["AcceleratedClock", "Clock", "RealClock"]


class Clock(ABC):
    """Source of time and of waiting, in *clock seconds*."""

    @property
    @abstractmethod
    def speed(self) -> float:
        """How many clock seconds pass per wall second."""

    @abstractmethod
    def time(self) -> float:
        """Current clock time as Unix seconds."""

    def now(self) -> datetime:
        """Current clock time as an aware UTC datetime."""
        return datetime.fromtimestamp(self.time(), tz=UTC)

    def to_wall(self, seconds: float) -> float:
        """Wall seconds that ``seconds`` of clock time take."""
        return seconds / self.speed

    async def sleep(self, seconds: float) -> None:
        """Wait ``seconds`` of clock time."""
        await asyncio.sleep(max(0.0, self.to_wall(seconds)))

    def timeout(self, seconds: float | None) -> asyncio.Timeout:
        """``async with clock.timeout(s):`` — raises ``TimeoutError`` after ``s`` clock seconds."""
        return asyncio.timeout(None if seconds is None else self.to_wall(seconds))


class RealClock(Clock):
    """The wall clock."""

    @property
    def speed(self) -> float:
        return 1.0

    def time(self) -> float:
        return time.time()


class AcceleratedClock(Clock):
    """A clock that starts at ``start`` and runs ``speed`` times faster than the wall clock.

    Args:
        start: Epoch the clock shows when created (aware datetime or ISO string; naive means UTC).
        speed: Clock seconds per wall second, > 0.
        wall_start: The wall-clock time at which the clock shows ``start``; by default the moment
            it is created. Modules in separate processes that share ``start``, ``speed`` and
            ``wall_start`` show the same time, however far apart they started.
    """

    def __init__(
        self, start: datetime | str, speed: float = 1.0, *, wall_start: datetime | str | None = None
    ) -> None:
        if not speed > 0:
            raise ValueError(f"clock speed must be > 0, got {speed}")
        self._start = _utc(start).timestamp()
        self._speed = float(speed)
        # Anchored to the monotonic clock when private, to the shared wall clock when synchronised.
        self._now: Callable[[], float] = time.monotonic if wall_start is None else time.time
        self._wall0 = time.monotonic() if wall_start is None else _utc(wall_start).timestamp()

    @property
    def speed(self) -> float:
        return self._speed

    def time(self) -> float:
        return self._start + (self._now() - self._wall0) * self._speed


def _utc(moment: datetime | str) -> datetime:
    """An aware datetime from a datetime or an ISO string; naive means UTC."""
    if isinstance(moment, str):
        moment = datetime.fromisoformat(moment)
    return moment.replace(tzinfo=UTC) if moment.tzinfo is None else moment
