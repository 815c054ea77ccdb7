"""A simulated flip-flat: a cover that takes time to swing and a light that takes time to settle."""

from __future__ import annotations

import asyncio
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.interfaces import CalibratorState, CoverState
from nightcrew.modules.calibrator import BaseCoverCalibrator

__all__ = ["SimCoverCalibrator"]


class SimCoverCalibrator(BaseCoverCalibrator):
    """A cover and flat-field light in the simulated observatory.

    Args:
        cover: Whether there is a cover (a panel on the dome wall has none).
        light: Whether there is a light (a dust cover has none).
        cover_time: Clock seconds the cover takes to open or close.
        warmup_time: Clock seconds the light takes to become stable after switching it on.
        max_brightness: Highest brightness.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        cover: bool = True,
        light: bool = True,
        cover_time: float = 10.0,
        warmup_time: float = 5.0,
        max_brightness: int = 255,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        for key, seconds in (("cover_time", cover_time), ("warmup_time", warmup_time)):
            if not seconds >= 0:
                raise ConfigError(f"must be >= 0 seconds, got {seconds}", key=key)
        if not max_brightness >= 1:
            raise ConfigError(f"must be >= 1, got {max_brightness}", key="max_brightness")
        self._cover_time, self._warmup_time = float(cover_time), float(warmup_time)
        self._max_brightness = int(max_brightness)
        self.cover = CoverState.CLOSED if cover else CoverState.NOT_PRESENT
        self.light = CalibratorState.OFF if light else CalibratorState.NOT_PRESENT
        self.brightness = 0
        self._halt = asyncio.Event()

    async def _hw_get_cover_state(self) -> CoverState:
        return self.cover

    async def _hw_move_cover(self, open_: bool) -> None:
        self.cover = CoverState.MOVING
        self._halt.clear()
        swing = asyncio.ensure_future(self.clock.sleep(self._cover_time))
        halted = asyncio.ensure_future(self._halt.wait())
        try:
            await asyncio.wait([swing, halted], return_when=asyncio.FIRST_COMPLETED)
        finally:
            swing.cancel()
            halted.cancel()
            await asyncio.gather(swing, halted, return_exceptions=True)
            if swing.cancelled():
                self.cover = CoverState.UNKNOWN  # halted (or cancelled) halfway
        if self.cover is CoverState.MOVING:
            self.cover = CoverState.OPEN if open_ else CoverState.CLOSED

    async def _hw_halt_cover(self) -> None:
        self._halt.set()

    async def _hw_get_calibrator_state(self) -> CalibratorState:
        return self.light

    async def _hw_calibrator_on(self, brightness: int) -> None:
        self.brightness, self.light = brightness, CalibratorState.NOT_READY
        await self.clock.sleep(self._warmup_time)
        self.light = CalibratorState.READY

    async def _hw_calibrator_off(self) -> None:
        self.brightness, self.light = 0, CalibratorState.OFF

    async def _hw_get_brightness(self) -> int:
        return self.brightness

    async def _hw_get_max_brightness(self) -> int:
        return self._max_brightness
