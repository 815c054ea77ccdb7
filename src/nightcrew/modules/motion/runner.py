"""One motion at a time: the task a moving device runs, with busy checks, pre-emption and abort.

A device (telescope, roof, focuser, ...) runs each motion through a :class:`MotionRunner`. A second
motion while one runs is refused with DeviceBusyError, unless it *pre-empts* (park, close on bad
weather, stop): then the running one is cancelled and its caller gets AbortedError. The motion
runs in its own task so that whoever stops it does not have to be the one who started it.
"""

from __future__ import annotations

import asyncio
from collections.abc import Coroutine
from typing import Any, TypeVar

from nightcrew.errors import AbortedError, DeviceBusyError

__all__ = ["MotionRunner"]

T = TypeVar("T")


class MotionRunner:
    """Runs the motions of one device (or one axis of it) one at a time.

    Args:
        device: Name used in error messages ("telescope", "dome rotation").
    """

    def __init__(self, device: str) -> None:
        self._device = device
        self._task: asyncio.Task[Any] | None = None
        self._action = ""
        self._aborted_by = ""

    @property
    def busy(self) -> bool:
        """Whether a motion is running."""
        return self._task is not None and not self._task.done()

    @property
    def action(self) -> str:
        """What the running motion does ("" when idle)."""
        return self._action if self.busy else ""

    def check_idle(self) -> None:
        """Raise DeviceBusyError if a motion is running (call before changing any state)."""
        if self.busy:
            raise DeviceBusyError(
                f"{self._device} is busy ({self._action}); wait for it or stop the motion first"
            )

    async def run(self, action: str, motion: Coroutine[Any, Any, T], *, preempt: bool = False) -> T:
        """Run ``motion``; with ``preempt``, abort a running motion first instead of refusing.

        Raises:
            DeviceBusyError: Another motion runs and ``preempt`` is False (``motion`` never starts).
            AbortedError: The motion was stopped or pre-empted by someone else.
        """
        if self.busy:
            if not preempt:
                motion.close()
                self.check_idle()
            await self.stop(f"pre-empted by {action}")
        self._action = action
        self._aborted_by = ""
        task = asyncio.get_running_loop().create_task(motion, name=f"{self._device}: {action}")
        self._task = task
        try:
            return await task
        except asyncio.CancelledError:
            current = asyncio.current_task()
            if task.cancelled() and self._aborted_by and not (current and current.cancelling()):
                raise AbortedError(f"{self._device}: {action} was aborted ({self._aborted_by})") from None
            raise

    async def join(self) -> None:
        """Wait until the running motion (if any) has ended, however it ends."""
        task = self._task
        if task is not None and not task.done():
            await asyncio.wait([task])

    async def stop(self, reason: str = "stopped") -> bool:
        """Cancel the running motion and wait until it has ended; returns whether one was running."""
        task = self._task
        if task is None or task.done():
            return False
        self._aborted_by = reason
        task.cancel()
        await asyncio.gather(task, return_exceptions=True)
        return True
