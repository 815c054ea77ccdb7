"""The base of every moving device: motion status, its event, and one motion at a time.

One safety rule lives here for every device that parks: without the message server nobody can
tell it to park (not the weather module, not the watchdog), so with ``park_when_offline`` set, a
device whose comm stayed disconnected for that many clock seconds parks by itself (a roof: closes).
Roofs and telescopes set it to 300 s by default. It may be used again once the comm is back.
"""

from __future__ import annotations

import logging
from abc import abstractmethod
from collections.abc import Awaitable, Coroutine
from typing import Any, TypeVar

from nightcrew.errors import ConfigError, MotionError, MoveError, NightcrewError
from nightcrew.events import MotionStatusChangedEvent
from nightcrew.interfaces import IMotion, ModuleState, MotionStatus
from nightcrew.modules.module import Module
from nightcrew.modules.motion.runner import MotionRunner

__all__ = ["BaseMotion"]

log = logging.getLogger(__name__)

T = TypeVar("T")

#: States in which a device is not ready for use.
_NOT_READY = frozenset({MotionStatus.PARKED, MotionStatus.ERROR, MotionStatus.UNKNOWN})


#: Clock seconds a module with ``park_on_close`` may take to park while closing.
PARK_ON_CLOSE_TIMEOUT = 300.0


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
        **kwargs: Module options.
    """

    #: Status before the first change; a parked telescope, a closed roof, an idle focuser.
    initial_status: MotionStatus = MotionStatus.IDLE

    def __init__(
        self, *, park_on_close: bool = False, park_when_offline: float | None = None, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        if park_when_offline is not None and not park_when_offline > 0:
            raise ConfigError(
                f"must be > 0 seconds or null, got {park_when_offline}", key="park_when_offline"
            )
        self._park_on_close = park_on_close
        self._park_when_offline = park_when_offline
        if park_when_offline is not None:
            self.add_background_task(self._offline_watch_loop)
        self._motion_status = self.initial_status
        self._motion = MotionRunner(type(self).__name__)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        self._motion = MotionRunner(self.name)
        await super().open()
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

    async def _offline_watch_loop(self) -> None:
        """Park when the comm stayed disconnected for ``park_when_offline`` clock seconds."""
        limit = self._park_when_offline
        assert limit is not None
        step = min(5.0, limit / 5)
        offline_since: float | None = None
        while True:
            now = self.clock.time()
            if self.comm.connected:
                offline_since = None
            elif offline_since is None:
                offline_since = now
            elif (
                now - offline_since >= limit
                and (self._motion_status is not MotionStatus.PARKED or self._motion.busy)
                and self._motion_status is not MotionStatus.PARKING
            ):
                log.warning(
                    "%s: no connection to the other modules for %.0f s: parking",
                    self.name,
                    now - offline_since,
                )
                try:
                    await self.park()
                except NightcrewError as exc:  # tried again on the next round
                    log.error("%s: could not park without the server: %s", self.name, exc)
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
