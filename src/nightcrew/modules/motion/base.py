"""The base of every moving device: motion status, its event, and one motion at a time."""

from __future__ import annotations

import logging
from abc import abstractmethod
from collections.abc import Awaitable, Coroutine
from typing import Any, TypeVar

from nightcrew.errors import MotionError, MoveError, NightcrewError
from nightcrew.events import MotionStatusChangedEvent
from nightcrew.interfaces import IMotion, ModuleState, MotionStatus
from nightcrew.modules.module import Module
from nightcrew.modules.motion.runner import MotionRunner

__all__ = ["BaseMotion"]

log = logging.getLogger(__name__)

T = TypeVar("T")

#: States in which a device is not ready for use.
_NOT_READY = frozenset({MotionStatus.PARKED, MotionStatus.ERROR, MotionStatus.UNKNOWN})


class BaseMotion(Module, IMotion):
    """A module driving one moving device.

    Subclasses run every motion through :meth:`_run_motion` and report status changes with
    :meth:`_set_motion_status`, which sends MotionStatusChangedEvent only when the status changes.
    ``stop_motion`` cancels the running motion (its caller gets AbortedError) and then calls the
    :meth:`_hw_stop` hook.
    """

    #: Status before the first change; a parked telescope, a closed roof, an idle focuser.
    initial_status: MotionStatus = MotionStatus.IDLE

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
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
        await self._motion.stop("module closing")
        await super().close()

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
