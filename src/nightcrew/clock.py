"""Clocks: every piece of nightcrew takes time from one of these, never from ``time`` directly.

A :class:`RealClock` follows the wall clock. An :class:`AcceleratedClock` starts at a chosen epoch
and runs ``speed`` times faster, so that a simulated night passes in minutes: ``sleep(60)`` on a
clock with speed 100 returns after 0.6 s of wall time, and ``now()`` has moved on by 60 s.
A :class:`VirtualClock` (one process only) runs the event loop on virtual time: the clock stands
still while anything is being done and jumps to the next wake-up when everything waits on it, so
the same inputs give the same night however fast or busy the machine is.

Work the observatory waits on (writing a frame, a plate solve, measuring focus or seeing, solving
the schedule) is declared with ``async with clock.work(kind):`` (kinds in :data:`WORK_COSTS`). On a
virtual clock it costs the clock seconds its model says, not what this machine took.

Computation is the exception: a plate solve that takes 1 s on this machine takes about 1 s at the
telescope too, but on a clock at speed 320 it would cost 320 s of sky. Work on the observing path
(reading out and writing a frame, analysing an acquisition or focus image) therefore runs inside
:meth:`Clock.computing`, during which an accelerated clock runs at real time (speed 1). Waiting on a
clock — :meth:`Clock.sleep`, :meth:`Clock.timeout` — is in clock seconds and allows for that.
"""

from __future__ import annotations

import asyncio
import contextlib
import math
import time
from abc import ABC, abstractmethod
from collections.abc import AsyncIterator, Callable, Iterator, Mapping
from datetime import UTC, datetime
from types import TracebackType

from nightcrew._virtual_loop import VirtualTime, virtual_time

__all__ = ["WORK_COSTS", "AcceleratedClock", "Clock", "ClockTimeout", "RealClock", "VirtualClock"]

#: Clock seconds each kind of work costs on a :class:`VirtualClock` unless its ``work`` option says
#: otherwise: close to what it takes at a small telescope with a modern PC.
WORK_COSTS: Mapping[str, float] = {
    "write_frame": 0.5,  # serialise a frame to FITS and write it (after the camera's read-out)
    "plate_solve": 5.0,  # astrometry.net on a 20' field with a position hint
    "measure_focus": 0.5,  # find the stars of a focus frame and their widths
    "measure_seeing": 0.5,  # the same on a science frame
    "schedule": 10.0,  # plan the rest of the night (runs beside the night, not in its way)
    "simulate": 0.0,  # the simulator's own work (rendering the sky): no time at a telescope
}
#: Work nobody waits on: an accelerated clock does not slow down for it.
_BESIDE_THE_NIGHT = frozenset({"schedule"})


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

    @contextlib.asynccontextmanager
    async def work(self, kind: str) -> AsyncIterator[None]:
        """``async with clock.work(kind):`` the work inside is ``kind`` (a key of WORK_COSTS).

        Here: a :meth:`computing` section (what the machine takes, at real time); a
        :class:`VirtualClock` charges the declared cost instead.
        """
        if _check_kind(kind) in _BESIDE_THE_NIGHT:
            yield
            return
        with self.computing():
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


class VirtualClock(Clock):
    """A clock on virtual time for an observatory in one process: deterministic and fast.

    The event loop it runs on (the running one when first used) is switched to virtual time
    (:mod:`nightcrew._virtual_loop`): clock time moves only when every task waits on the clock —
    nothing ready to run, no worker-thread job undelivered, no :meth:`work` section open — and
    then jumps to the earliest wake-up. Results of worker threads reach their tasks one at a time
    in the order they were asked for, so the night never depends on thread timing. Every
    ``asyncio`` timer on that loop runs on the same virtual time.

    Work sections cost what ``work`` declares: their body takes no clock time at all, and the
    task then waits the declared seconds on the clock (the others carry on meanwhile).

    Args:
        start: Epoch the clock shows when first used (aware datetime or ISO string; naive is UTC).
        work: Clock seconds per kind of work, replacing the defaults of :data:`WORK_COSTS`.
    """

    def __init__(self, start: datetime | str, *, work: Mapping[str, float] | None = None) -> None:
        self._start = _utc(start).timestamp()
        costs = dict(WORK_COSTS)
        for kind, seconds in (work or {}).items():
            _check_kind(kind)
            if not (isinstance(seconds, int | float) and math.isfinite(seconds) and seconds >= 0):
                raise ValueError(f"work.{kind}: need a number of clock seconds >= 0, got {seconds!r}")
            costs[kind] = float(seconds)
        self.costs: Mapping[str, float] = costs
        self._virtual: VirtualTime | None = None
        self._origin = 0.0

    @property
    def speed(self) -> float:
        return 1.0  # the loop's own time is clock time

    def time(self) -> float:
        virtual = self._attached()
        return self._start if virtual is None else self._start + virtual.now - self._origin

    def attach(self, loop: asyncio.AbstractEventLoop | None = None) -> None:
        """Run on ``loop`` (default: the running one), switching it to virtual time if needed."""
        if self._virtual is None:
            self._virtual = virtual_time(loop)
            self._origin = self._virtual.now
        elif loop is not None and loop is not self._virtual.loop:
            raise RuntimeError("a VirtualClock runs on one event loop")

    def _attached(self) -> VirtualTime | None:
        if self._virtual is None:
            try:
                self.attach()
            except RuntimeError:  # no running loop yet: the clock shows its start
                return None
        return self._virtual

    @contextlib.asynccontextmanager
    async def work(self, kind: str) -> AsyncIterator[None]:
        cost = self.costs[_check_kind(kind)]
        virtual = self._attached()
        if virtual is None:
            raise RuntimeError("VirtualClock.work() needs a running event loop")
        with virtual.hold():
            yield
        await self.sleep(cost)

    async def sleep(self, seconds: float) -> None:
        self._attached()
        await asyncio.sleep(max(0.0, seconds))

    def wall_waited(self) -> dict[str, float]:
        """Wall seconds the loop stood waiting, by thread job (``Class.method``) and ``hold``
        (work waiting on the outside world), largest first: where the wall time of a run went."""
        waited = self._virtual.waited if self._virtual is not None else {}
        return dict(sorted(waited.items(), key=lambda item: -item[1]))


def _check_kind(kind: str) -> str:
    if kind not in WORK_COSTS:
        raise ValueError(f"unknown kind of work {kind!r}; known: {', '.join(WORK_COSTS)}")
    return kind


def _utc(moment: datetime | str) -> datetime:
    """An aware datetime from a datetime or an ISO string; naive means UTC."""
    if isinstance(moment, str):
        moment = datetime.fromisoformat(moment)
    return moment.replace(tzinfo=UTC) if moment.tzinfo is None else moment
