"""A simulated field rotator: turns at a fixed speed the short way round and can stop anywhere."""

from __future__ import annotations

from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.modules.roof import azimuth_difference
from nightcrew.modules.rotator import BaseRotator

__all__ = ["SimRotator"]


class SimRotator(BaseRotator):
    """A rotator in the simulated observatory.

    Args:
        speed: Degrees per second.
        sky_offset: Sky position angle minus mechanical angle, in degrees (what a sync would set).
        **kwargs: Module options.
    """

    def __init__(self, *, speed: float = 5.0, sky_offset: float = 0.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not speed > 0:
            raise ConfigError(f"must be > 0 deg/s, got {speed}", key="speed")
        self._speed = float(speed)
        self._sky_offset = float(sky_offset)
        self._reversed = False
        self._at = 0.0  # degrees, where the last move ended
        #: The move under way: (start, signed turn, clock time started, duration), or None.
        self._travel: tuple[float, float, float, float] | None = None

    @property
    def mechanical(self) -> float:
        """Degrees where the rotator is now, also in the middle of a move."""
        if self._travel is None:
            return self._at
        start, turn, started, duration = self._travel
        done = min(1.0, (self.clock.time() - started) / duration) if duration > 0 else 1.0
        return (start + done * turn) % 360.0

    async def _hw_move_mechanical(self, angle: float) -> None:
        turn = azimuth_difference(angle, self._at)
        duration = abs(turn) / self._speed
        self._travel = (self._at, turn, self.clock.time(), duration)
        try:
            await self.clock.sleep(duration)
        except BaseException:
            self._at = self.mechanical  # halted: it stays where it is now
            raise
        finally:
            self._travel = None
        self._at = angle % 360.0

    def _sign(self) -> float:
        return -1.0 if self._reversed else 1.0

    async def _hw_move_position_angle(self, angle: float) -> None:
        await self._hw_move_mechanical((self._sign() * (angle - self._sky_offset)) % 360.0)

    async def _hw_get_position_angle(self) -> float:
        return (self._sign() * self.mechanical + self._sky_offset) % 360.0

    async def _hw_get_mechanical_angle(self) -> float:
        return self.mechanical

    async def _hw_set_reversed(self, reverse: bool) -> None:
        self._reversed = reverse

    async def _hw_get_reversed(self) -> bool:
        return self._reversed

    async def _hw_stop(self) -> None:
        """The rotator stays where the cancelled move left it."""
