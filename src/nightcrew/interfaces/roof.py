"""Roofs and domes, which protect the telescope and are the first thing bad weather closes."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.motion import IMotion
from nightcrew.interfaces.quantities import Azimuth
from nightcrew.timeout import timeout

__all__ = ["IDome", "IRoof"]


class IRoof(IMotion):
    """A roof or shutter; stop_motion stops it halfway."""

    @timeout(300)
    @abstractmethod
    async def open_roof(self) -> None:
        """Open the roof completely."""

    @timeout(300)
    @abstractmethod
    async def close_roof(self) -> None:
        """Close the roof completely."""


class IDome(IRoof):
    """A rotating dome: a roof (its shutter) with an azimuth to follow the telescope."""

    @timeout(300)
    @abstractmethod
    async def move_azimuth(self, az: Azimuth) -> None:
        """Turn the slit to azimuth ``az`` in degrees east of north."""

    @abstractmethod
    async def get_azimuth(self) -> float:
        """Azimuth of the slit in degrees east of north."""
