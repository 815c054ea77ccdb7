"""Small, generic interfaces for things that run, can be started, stopped or aborted."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.base import Interface
from nightcrew.timeout import timeout

__all__ = ["IAbortable", "IReady", "IRunnable", "IRunning", "IStartStop"]


class IAbortable(Interface):
    """An action in progress can be aborted."""

    @abstractmethod
    async def abort(self) -> None:
        """Abort the current action; the aborted call raises AbortedError."""


class IReady(Interface):
    """The module can say whether it is ready for use."""

    @abstractmethod
    async def is_ready(self) -> bool:
        """Whether the device is ready (initialised, not in error)."""


class IRunning(Interface):
    """The module has an activity that may be running."""

    @abstractmethod
    async def is_running(self) -> bool:
        """Whether the activity is running."""


class IStartStop(IRunning):
    """A continuous activity (a loop) that can be started and stopped."""

    @abstractmethod
    async def start(self) -> None:
        """Start the activity; returns once it started."""

    @abstractmethod
    async def stop(self) -> None:
        """Stop the activity; returns once it stopped."""


class IRunnable(IAbortable):
    """A finite action that runs to its end when asked."""

    @timeout(3600)
    @abstractmethod
    async def run(self) -> None:
        """Run the action and return when it is done."""
