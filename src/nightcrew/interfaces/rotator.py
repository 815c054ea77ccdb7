"""Field rotators, which turn the camera about the optical axis. Angles in degrees."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.motion import IMotion
from nightcrew.interfaces.quantities import Angle
from nightcrew.timeout import timeout

__all__ = ["IRotator"]


class IRotator(IMotion):
    """A rotator: a sky position angle (mechanical angle plus a sync offset) that it can move to.

    ``stop_motion`` halts a running move where it is.
    """

    @timeout(300)
    @abstractmethod
    async def move_position_angle(self, angle: Angle) -> None:
        """Turn to sky position angle ``angle`` in degrees (0..360)."""

    @timeout(300)
    @abstractmethod
    async def move_position_angle_by(self, delta: Angle) -> None:
        """Turn by ``delta`` degrees from the current position angle (negative turns back)."""

    @abstractmethod
    async def get_position_angle(self) -> float:
        """Current sky position angle in degrees (0..360)."""

    @timeout(300)
    @abstractmethod
    async def move_mechanical(self, angle: Angle) -> None:
        """Turn to mechanical angle ``angle`` in degrees (0..360), ignoring the sync offset."""

    @abstractmethod
    async def get_mechanical_angle(self) -> float:
        """Current mechanical angle in degrees (0..360)."""

    @abstractmethod
    async def set_rotator_reversed(self, reverse: bool) -> None:
        """Whether the rotator turns the other way (for optical trains that mirror the image)."""

    @abstractmethod
    async def get_rotator_reversed(self) -> bool:
        """Whether the rotator turns the other way."""
