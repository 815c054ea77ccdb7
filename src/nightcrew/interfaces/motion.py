"""The interface of everything that moves: telescopes, roofs, domes, focusers, filter wheels."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.control import IReady
from nightcrew.interfaces.enums import MotionStatus
from nightcrew.timeout import timeout

__all__ = ["IMotion"]


class IMotion(IReady):
    """A device that can be initialised, parked and stopped, and reports its motion status.

    A module may drive several devices (e.g. a mount and its focuser, or a dome: its ``azimuth``
    rotation beside the shutter); ``device`` then names one of them, and None (or a name the module
    does not have) means the module as a whole.
    """

    @timeout(300)
    @abstractmethod
    async def init(self) -> None:
        """Initialise the device (home, unpark, power on) and leave it idle."""

    @timeout(300)
    @abstractmethod
    async def park(self) -> None:
        """Move the device into its safe parking position."""

    @abstractmethod
    async def stop_motion(self, device: str | None = None) -> None:
        """Stop any motion of ``device`` (or of all devices: None, or a name the module lacks) now."""

    @abstractmethod
    async def get_motion_status(self, device: str | None = None) -> MotionStatus:
        """Motion status of ``device``, or of the module as a whole (None, or a name the module lacks)."""
