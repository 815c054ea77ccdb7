"""The base of every moving device: motion status, its event, and one motion at a time.

Two safety rules live here for every device that parks, both on the module's clock:

* Without the message server nobody can tell it to park (not the weather module, not the watchdog),
  so with ``park_when_offline`` set, a device whose comm stayed disconnected for that many clock
  seconds parks by itself (a roof: closes). Roofs and telescopes set it to 300 s by default. It may
  be used again once the comm is back.
* A dead-man's switch: with ``watchdog`` naming the safety watchdog, the device parks by itself when
  no WatchdogHeartbeatEvent from that module arrived for ``park_when_watchdog_silent`` clock seconds
  (a frozen or dead watchdog cannot close the roof when it should). The limit counts from the
  module's start; the device may be used again once the heartbeat is back (a roof refuses to open
  until then).
"""

from __future__ import annotations

import logging
import math
from abc import abstractmethod
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any, TypeVar

from nightcrew.errors import ConfigError, MotionError, MoveError, NightcrewError
from nightcrew.events import MotionStatusChangedEvent, WatchdogHeartbeatEvent
from nightcrew.interfaces import IMotion, ModuleState, MotionStatus
from nightcrew.modules.module import Module
from nightcrew.modules.motion.runner import MotionRunner
from nightcrew.timeout import method_timeout, wall_allowance

__all__ = ["BaseMotion"]

log = logging.getLogger(__name__)

T = TypeVar("T")

#: States in which a device is not ready for use.
_NOT_READY = frozenset({MotionStatus.PARKED, MotionStatus.ERROR, MotionStatus.UNKNOWN})


#: Clock seconds a module with ``park_on_close`` may take to park while closing.
PARK_ON_CLOSE_TIMEOUT = 300.0
#: Clock seconds a move may take beyond the travel time a driver computes from its rates.
MOVE_MARGIN = 30.0


class BaseMotion(Module, IMotion):
    """A module driving one moving device.

    Subclasses run every motion through :meth:`_run_motion` and report status changes with
    :meth:`_set_motion_status`, which sends MotionStatusChangedEvent only when the status changes.
    ``stop_motion`` cancels the running motion (its caller gets AbortedError) and then calls the
    :meth:`_hw_stop` hook.

    Args:
        park_on_close: Park (a roof: close) before the module closes, e.g. when ``nightcrew up``
            or systemd stops it; bounded by :data:`PARK_ON_CLOSE_TIMEOUT` clock seconds.
        park_when_offline: Clock seconds without a connection to the other modules (the XMPP
            server) after which the device parks by itself; None: never.
        watchdog: The safety watchdog module whose heartbeat this device needs (None: none).
        park_when_watchdog_silent: Clock seconds without a heartbeat from ``watchdog`` after which
            the device parks by itself (> 0; more than the watchdog's ``interval`` plus twice its
            ``answer_timeout``, the longest it takes for a round).
        **kwargs: Module options.
    """

    #: Status before the first change; a parked telescope, a closed roof, an idle focuser.
    initial_status: MotionStatus = MotionStatus.IDLE

    def __init__(
        self,
        *,
        park_on_close: bool = False,
        park_when_offline: float | None = None,
        watchdog: str | None = None,
        park_when_watchdog_silent: float = 120.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if park_when_offline is not None and not park_when_offline > 0:
            raise ConfigError(
                f"must be > 0 seconds or null, got {park_when_offline}", key="park_when_offline"
            )
        if not (math.isfinite(park_when_watchdog_silent) and park_when_watchdog_silent > 0):
            raise ConfigError(
                f"must be > 0 seconds (finite), got {park_when_watchdog_silent}",
                key="park_when_watchdog_silent",
            )
        if watchdog is not None and not watchdog:
            raise ConfigError("name the watchdog module, or leave the key out", key="watchdog")
        self._park_on_close = park_on_close
        self._park_when_offline = park_when_offline
        self._offline_since: float | None = None
        self._watchdog = watchdog
        self._watchdog_limit = float(park_when_watchdog_silent)
        self._watchdog_beat = 0.0  # clock time of its last heartbeat (of our start, before the first)
        if park_when_offline is not None or watchdog is not None:
            self.add_background_task(self._park_by_itself_loop)
        self._motion_status = self.initial_status
        self._motion = MotionRunner(type(self).__name__)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        self._motion = MotionRunner(self.name)
        self._watchdog_beat = self.clock.time()
        await super().open()
        if self._watchdog is not None:
            await self.comm.register_event(WatchdogHeartbeatEvent, self._on_watchdog_heartbeat)
        # Announce the starting status so that late listeners (web, mastermind) know it.
        await self.comm.send_event(MotionStatusChangedEvent(status=self._motion_status))

    async def close(self) -> None:
        if self._park_on_close and self.state in (ModuleState.READY, ModuleState.ERROR):
            await self._park_before_closing()
        await self._motion.stop("module closing")
        await super().close()

    async def _park_before_closing(self) -> None:
        if self._motion_status is MotionStatus.PARKED and not self._motion.busy:
            return
        log.info("%s: parking before closing", self.name)
        try:
            async with self.clock.timeout(PARK_ON_CLOSE_TIMEOUT):
                await self.park()
        except Exception as exc:  # closing goes on: a stop must not hang on a broken device
            log.error("%s: could not park before closing: %s", self.name, exc or type(exc).__name__)

    async def _on_watchdog_heartbeat(self, event: WatchdogHeartbeatEvent, sender: str) -> None:
        if sender == self._watchdog:  # another module's beat must not stand in for the watchdog's
            self._watchdog_beat = self.clock.time()

    def _watchdog_silence(self) -> str | None:
        """Why the watchdog counts as silent (the dead-man's switch is released), or None."""
        if self._watchdog is None:
            return None
        silent = self.clock.time() - self._watchdog_beat
        if silent <= self._watchdog_limit:
            return None
        return (
            f"no heartbeat from the watchdog '{self._watchdog}' for {silent:.0f} s "
            f"(limit {self._watchdog_limit:g} s)"
        )

    def _offline_for_too_long(self) -> str | None:
        """Why the device must park for want of the message server, or None."""
        if self._park_when_offline is None:
            return None
        now = self.clock.time()
        if self.comm.connected:
            self._offline_since = None
        elif self._offline_since is None:
            self._offline_since = now
        elif now - self._offline_since >= self._park_when_offline:
            return f"no connection to the other modules for {now - self._offline_since:.0f} s"
        return None

    async def _park_by_itself_loop(self) -> None:
        """Park when the comm stayed disconnected or the watchdog silent for too long."""
        limits = [self._watchdog_limit] if self._watchdog is not None else []
        limits += [self._park_when_offline] if self._park_when_offline is not None else []
        step = min(5.0, *(limit / 5 for limit in limits))
        while True:
            reason = self._offline_for_too_long() or self._watchdog_silence()
            if (
                reason is not None
                and (self._motion_status is not MotionStatus.PARKED or self._motion.busy)
                and self._motion_status is not MotionStatus.PARKING
            ):
                log.warning("%s: %s: parking", self.name, reason)
                try:
                    await self.park()
                except NightcrewError as exc:  # tried again on the next round
                    log.error("%s: could not park (%s): %s", self.name, reason, exc)
            await self.clock.sleep(step)

    # --- helpers for subclasses ----------------------------------------------------------------

    async def _set_motion_status(self, status: MotionStatus) -> None:
        """Change the status and tell the others (only if it changed)."""
        if status is self._motion_status:
            return
        log.info("%s: motion status %s -> %s", self.name, self._motion_status, status)
        self._motion_status = status
        if self.comm.is_open:
            await self.comm.send_event(MotionStatusChangedEvent(status=status))

    async def _run_motion(self, action: str, motion: Coroutine[Any, Any, T], *, preempt: bool = False) -> T:
        """Run ``motion`` as the device's only motion (see MotionRunner.run)."""
        return await self._motion.run(action, motion, preempt=preempt)

    async def _guarded(self, hardware: Awaitable[T], failure: str, error: type[MotionError] = MoveError) -> T:
        """Await a hardware hook; on failure go to ERROR status and raise ``error`` naming ``failure``."""
        try:
            return await hardware
        except NightcrewError:
            await self._set_motion_status(MotionStatus.ERROR)
            raise
        except Exception as exc:
            await self._set_motion_status(MotionStatus.ERROR)
            raise error(f"{failure}: {type(exc).__name__}: {exc}") from exc

    # --- hooks ---------------------------------------------------------------------------------

    def _announced_move_timeout(
        self, travel: Callable[[], float | None], declared: Callable[..., Any]
    ) -> float:
        """The timeout a move announces: ``travel()`` (clock seconds the driver expects the move to
        take, from its rates; None when it does not know) plus :data:`MOVE_MARGIN` and the wall
        allowance (:func:`~nightcrew.timeout.wall_allowance`), or the ``declared`` interface
        method's fixed timeout when the travel time is unknown."""
        try:
            seconds = travel()
        except (ValueError, ArithmeticError):
            seconds = None  # a target the move itself refuses: it fails at once anyway
        if seconds is None or not math.isfinite(seconds) or seconds < 0:
            return method_timeout(declared, {})
        return seconds + MOVE_MARGIN + wall_allowance(self.clock.speed)

    @abstractmethod
    async def _hw_stop(self) -> None:
        """Stop the hardware where it is (called after the running motion task was cancelled)."""

    def _status_after_stop(self) -> MotionStatus:
        """Status after stop_motion(); IDLE unless a subclass knows better."""
        return MotionStatus.IDLE

    # --- IMotion -------------------------------------------------------------------------------

    async def stop_motion(self, device: str | None = None) -> None:
        await self._motion.stop("stop_motion() called")
        await self._hw_stop()
        await self._set_motion_status(self._status_after_stop())

    async def get_motion_status(self, device: str | None = None) -> MotionStatus:
        return self._motion_status

    async def is_ready(self) -> bool:
        return self._motion_status not in _NOT_READY
