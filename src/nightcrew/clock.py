"""Clocks: every piece of nightcrew takes time from one of these, never from ``time`` directly.

A :class:`RealClock` follows the wall clock. An :class:`AcceleratedClock` starts at a chosen epoch
and runs ``speed`` times faster, so that a simulated night passes in minutes: ``sleep(60)`` on a
clock with speed 100 returns after 0.6 s of wall time, and ``now()`` has moved on by 60 s.

Computation is the exception: a plate solve that takes 1 s on this machine takes about 1 s at the
telescope too, but on a clock at speed 320 it would cost 320 s of sky. Work on the observing path
(reading out and writing a frame, analysing an acquisition or focus image) therefore runs inside
:meth:`Clock.computing`, during which an accelerated clock runs at real time (speed 1). Waiting on a
clock — :meth:`Clock.sleep`, :meth:`Clock.timeout` — is in clock seconds and allows for that.
"""

from __future__ import annotations

import asyncio
import contextlib
import time
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator
from datetime import UTC, datetime
from types import TracebackType

__all__ = ["AcceleratedClock", "Clock", "ClockTimeout", "RealClock"]


class Clock(ABC):
    """Source of time and of waiting, in *clock seconds*."""

    @property
    @abstractmethod
    def speed(self) -> float:
        """How many clock seconds pass per wall second (outside :meth:`computing`)."""

    @abstractmethod
    def time(self) -> float:
        """Current clock time as Unix seconds."""

    def now(self) -> datetime:
        """Current clock time as an aware UTC datetime."""
        return datetime.fromtimestamp(self.time(), tz=UTC)

    def to_wall(self, seconds: float) -> float:
        """Wall seconds that ``seconds`` of clock time take (outside :meth:`computing`)."""
        return seconds / self.speed

    def lag(self) -> float:
        """Wall seconds the clock has fallen behind ``speed`` so far by running at real time."""
        return 0.0

    @contextlib.contextmanager
    def computing(self) -> Iterator[None]:
        """``with clock.computing():`` the work inside takes as much clock time as wall time.

        For computation the observatory waits on, which a fast clock must not multiply. The whole
        (simulated) world slows down with it. Sections may nest and overlap.
        """
        yield

    async def sleep(self, seconds: float) -> None:
        """Wait ``seconds`` of clock time."""
        await asyncio.sleep(max(0.0, self.to_wall(seconds)))

    def timeout(self, seconds: float | None, *, grace: float = 0.0) -> ClockTimeout:
        """``async with clock.timeout(s):`` raises ``TimeoutError`` after ``s`` clock seconds and
        ``grace`` more wall seconds (time the network takes, which a fast clock does not shrink)."""
        return ClockTimeout(self, seconds, grace)


class ClockTimeout:
    """An ``asyncio.timeout`` in clock seconds: it waits longer when the clock ran at real time."""

    def __init__(self, clock: Clock, seconds: float | None, grace: float) -> None:
        self._clock, self._seconds, self._grace = clock, seconds, grace
        self._inner = asyncio.timeout(None)
        self._handle: asyncio.TimerHandle | None = None
        self._deadline = 0.0  # clock time

    async def __aenter__(self) -> ClockTimeout:
        await self._inner.__aenter__()
        self.reschedule(self._seconds)
        return self

    async def __aexit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        if self._handle is not None:
            self._handle.cancel()
        await self._inner.__aexit__(exc_type, exc, tb)  # turns our cancellation into TimeoutError

    def expired(self) -> bool:
        """Whether the timeout fired."""
        return self._inner.expired()

    def reschedule(self, seconds: float | None) -> None:
        """Expire ``seconds`` of clock time (plus the grace) from now; ``None``: never."""
        if self._handle is not None:
            self._handle.cancel()
            self._handle = None
        self._inner.reschedule(None)
        if seconds is not None:
            self._deadline = self._clock.time() + max(0.0, seconds)
            self._check()

    def _check(self) -> None:
        loop = asyncio.get_running_loop()
        remaining = self._deadline - self._clock.time()
        if remaining > 0:  # woken early if the clock ran at real time meanwhile: wait on
            self._handle = loop.call_later(self._clock.to_wall(remaining), self._check)
        else:
            self._handle = None
            self._inner.reschedule(loop.time() + self._grace)


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
            ``wall_start`` show the same time, however far apart they started. Such a clock
            ignores :meth:`computing`: one process slowing down would split the observatory's time.
    """

    def __init__(
        self, start: datetime | str, speed: float = 1.0, *, wall_start: datetime | str | None = None
    ) -> None:
        if not speed > 0:
            raise ValueError(f"clock speed must be > 0, got {speed}")
        self._start = _utc(start).timestamp()
        self._speed = float(speed)
        self._shared = wall_start is not None
        # Anchored to the monotonic clock when private, to the shared wall clock when synchronised.
        self._now: Callable[[], float] = time.monotonic if wall_start is None else time.time
        self._wall0 = time.monotonic() if wall_start is None else _utc(wall_start).timestamp()
        self._sections = 0
        self._lag = 0.0  # wall seconds behind, from finished computing sections
        self._section_began = 0.0

    @property
    def speed(self) -> float:
        return self._speed

    def time(self) -> float:
        return self._start + (self._now() - self._wall0 - self.lag()) * self._speed

    def lag(self) -> float:
        if self._sections == 0:
            return self._lag
        return self._lag + (self._now() - self._section_began) * self._slowdown

    @property
    def _slowdown(self) -> float:
        # A wall second inside a section is one clock second: 1 - 1/speed wall seconds of lag.
        return max(0.0, 1.0 - 1.0 / self._speed)

    @contextlib.contextmanager
    def computing(self) -> Iterator[None]:
        if self._shared:
            yield
            return
        if self._sections == 0:
            self._section_began = self._now()
        self._sections += 1
        try:
            yield
        finally:
            self._sections -= 1
            if self._sections == 0:
                self._lag += (self._now() - self._section_began) * self._slowdown

    async def sleep(self, seconds: float) -> None:
        deadline, remaining = self.time() + seconds, seconds
        while True:
            await asyncio.sleep(max(0.0, self.to_wall(remaining)))
            # Woken when the wait would end at full speed; computing sections may have slowed it.
            remaining = deadline - self.time()
            if remaining <= 0:
                return


def _utc(moment: datetime | str) -> datetime:
    """An aware datetime from a datetime or an ISO string; naive means UTC."""
    if isinstance(moment, str):
        moment = datetime.fromisoformat(moment)
    return moment.replace(tzinfo=UTC) if moment.tzinfo is None else moment
