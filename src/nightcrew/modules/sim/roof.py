"""A simulated roof and dome: the shutter takes time to travel and can stop anywhere."""

from __future__ import annotations

import asyncio
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.modules.roof import BaseDome, BaseRoof, azimuth_difference

__all__ = ["SimDome", "SimRoof"]


class SimRoof(BaseRoof):
    """A roof in the simulated observatory.

    Args:
        open_time: Seconds to open completely.
        close_time: Seconds to close completely.
        **kwargs: Module options.
    """

    def __init__(self, *, open_time: float = 60.0, close_time: float = 60.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not (open_time > 0 and close_time > 0):
            raise ConfigError(
                f"open_time and close_time must be > 0 s, got {open_time}, {close_time}", key="open_time"
            )
        self._open_time, self._close_time = float(open_time), float(close_time)
        self.opened = 0.0  # fraction open, 0..1

    async def _travel(self, target: float, full_time: float) -> None:
        start, started = self.opened, self.clock.time()
        duration = abs(target - start) * full_time
        try:
            await self.clock.sleep(duration)
        except asyncio.CancelledError:
            f = min(1.0, (self.clock.time() - started) / duration) if duration > 0 else 1.0
            self.opened = start + f * (target - start)
            raise
        self.opened = target

    async def _hw_open(self) -> None:
        await self._travel(1.0, self._open_time)

    async def _hw_close(self) -> None:
        await self._travel(0.0, self._close_time)

    async def _hw_stop(self) -> None:
        """The shutter stays where the cancelled travel left it."""


class SimDome(SimRoof, BaseDome):
    """A dome in the simulated observatory: SimRoof's shutter plus a rotating slit.

    Args:
        rotation_speed: Degrees per second.
        **kwargs: Roof options, dome options (``follow``, ``follow_tolerance``, ``follow_interval``)
            and module options.
    """

    def __init__(self, *, rotation_speed: float = 5.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not rotation_speed > 0:
            raise ConfigError(f"must be > 0 deg/s, got {rotation_speed}", key="rotation_speed")
        self._rotation_speed = float(rotation_speed)
        self._azimuth = 0.0

    async def _hw_move_azimuth(self, az: float) -> None:
        start, started = self._azimuth, self.clock.time()
        turn = azimuth_difference(az, start)
        duration = abs(turn) / self._rotation_speed
        try:
            await self.clock.sleep(duration)
        except asyncio.CancelledError:
            f = min(1.0, (self.clock.time() - started) / duration) if duration > 0 else 1.0
            self._azimuth = (start + f * turn) % 360.0
            raise
        self._azimuth = az % 360.0

    async def _hw_get_azimuth(self) -> float:
        return self._azimuth
