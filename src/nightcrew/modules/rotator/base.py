"""Field rotators: moves to a sky position angle, by an offset, or to a mechanical angle.

Angles are degrees; absolute ones are taken modulo 360. A rotator has nothing to park or home:
``init()`` and ``park()`` leave it where it is. ``stop_motion`` halts a move (its caller gets
AbortedError). FITS cards: ROTPA (sky position angle) and ROTMECH (mechanical angle).
"""

from __future__ import annotations

import math
from abc import abstractmethod
from collections.abc import Awaitable, Callable

from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import FitsCard, IFitsHeaderBefore, IRotator, MotionStatus
from nightcrew.modules.motion import BaseMotion

__all__ = ["BaseRotator"]


class BaseRotator(BaseMotion, IRotator, IFitsHeaderBefore):
    """A rotator; a driver implements the ``_hw_*`` hooks (reversing is optional)."""

    # --- hooks ---------------------------------------------------------------------------------

    @abstractmethod
    async def _hw_move_position_angle(self, angle: float) -> None:
        """Turn to sky position angle ``angle`` (0..360); return when there."""

    async def _hw_move_position_angle_by(self, delta: float) -> None:
        """Turn by ``delta`` degrees; return when there (by default an absolute move)."""
        await self._hw_move_position_angle((await self._hw_get_position_angle() + delta) % 360.0)

    @abstractmethod
    async def _hw_move_mechanical(self, angle: float) -> None:
        """Turn to mechanical angle ``angle`` (0..360); return when there."""

    @abstractmethod
    async def _hw_get_position_angle(self) -> float:
        """Sky position angle in degrees."""

    @abstractmethod
    async def _hw_get_mechanical_angle(self) -> float:
        """Mechanical angle in degrees."""

    async def _hw_set_reversed(self, reverse: bool) -> None:
        """Turn the other way (for mirrored optical trains); by default not possible."""
        raise NotSupportedError(f"{self.name} cannot reverse its direction")

    async def _hw_get_reversed(self) -> bool:
        """Whether the rotator turns the other way."""
        return False

    # --- moves ---------------------------------------------------------------------------------

    @staticmethod
    def _finite(angle: float, what: str) -> float:
        if not math.isfinite(angle):
            raise InvalidArgumentError(f"{what}: the angle must be a finite number of degrees, got {angle}")
        return float(angle)

    async def _move(self, what: str, hardware: Callable[[], Awaitable[None]]) -> None:
        self._motion.check_idle()

        async def motion() -> None:
            await self._set_motion_status(MotionStatus.MOVING)
            await self._guarded(hardware(), f"rotator failed {what}")
            await self._set_motion_status(MotionStatus.IDLE)

        await self._run_motion(what, motion())

    async def move_position_angle(self, angle: float) -> None:
        what = f"turning to PA {angle}°"
        target = self._finite(angle, what) % 360.0
        await self._move(what, lambda: self._hw_move_position_angle(target))

    async def move_position_angle_by(self, delta: float) -> None:
        what = f"turning by {delta}°"
        offset = self._finite(delta, what)
        await self._move(what, lambda: self._hw_move_position_angle_by(offset))

    async def move_mechanical(self, angle: float) -> None:
        what = f"turning to mechanical angle {angle}°"
        target = self._finite(angle, what) % 360.0
        await self._move(what, lambda: self._hw_move_mechanical(target))

    async def get_position_angle(self) -> float:
        return await self._hw_get_position_angle() % 360.0

    async def get_mechanical_angle(self) -> float:
        return await self._hw_get_mechanical_angle() % 360.0

    async def set_rotator_reversed(self, reverse: bool) -> None:
        self._motion.check_idle()
        await self._hw_set_reversed(bool(reverse))

    async def get_rotator_reversed(self) -> bool:
        return await self._hw_get_reversed()

    async def init(self) -> None:
        """Nothing to home; a rotator is ready where it is."""
        await self._set_motion_status(MotionStatus.IDLE)

    async def park(self) -> None:
        """Nothing to park; stays where it is."""

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        return {
            "ROTPA": (round(await self.get_position_angle(), 3), "Rotator sky position angle [deg]"),
            "ROTMECH": (round(await self.get_mechanical_angle(), 3), "Rotator mechanical angle [deg]"),
        }
