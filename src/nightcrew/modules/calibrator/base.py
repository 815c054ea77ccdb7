"""Telescope covers and flat-field lights (flip-flats, panels): what a dome-flat script drives.

The base refuses what a device cannot do before it reaches the hardware - a part the device lacks
(NOT_PRESENT: NotSupportedError), a brightness beyond the light's maximum (InvalidArgumentError) -
and checks where a part ended up: a cover not open (closed) after opening (closing) is a
MoveError, a light not READY (OFF) after switching it on (off) a CalibratorError.
"""

from __future__ import annotations

from abc import abstractmethod
from collections.abc import Awaitable

from nightcrew.errors import CalibratorError, InvalidArgumentError, MoveError, NotSupportedError
from nightcrew.interfaces import CalibratorState, CoverState, ICoverCalibrator
from nightcrew.modules.module import Module

__all__ = ["BaseCoverCalibrator"]


class BaseCoverCalibrator(Module, ICoverCalibrator):
    """A cover and/or flat-field light; a driver implements the ``_hw_*`` hooks."""

    @property
    def calibrator_device(self) -> str:
        """The device's name in error messages."""
        return self.name

    # --- hooks ---------------------------------------------------------------------------------

    @abstractmethod
    async def _hw_get_cover_state(self) -> CoverState:
        """Where the cover is (NOT_PRESENT without one)."""

    @abstractmethod
    async def _hw_move_cover(self, open_: bool) -> None:
        """Open (``open_``) or close the cover; return when it has stopped moving."""

    @abstractmethod
    async def _hw_halt_cover(self) -> None:
        """Stop the cover where it is."""

    @abstractmethod
    async def _hw_get_calibrator_state(self) -> CalibratorState:
        """What the light is doing (NOT_PRESENT without one)."""

    @abstractmethod
    async def _hw_calibrator_on(self, brightness: int) -> None:
        """Switch the light on at ``brightness`` (checked); return when it is stable."""

    @abstractmethod
    async def _hw_calibrator_off(self) -> None:
        """Switch the light off; return when it is off."""

    @abstractmethod
    async def _hw_get_brightness(self) -> int:
        """Current brightness."""

    @abstractmethod
    async def _hw_get_max_brightness(self) -> int:
        """Highest brightness."""

    # --- checks --------------------------------------------------------------------------------

    async def _cover_present(self) -> None:
        if await self._hw_get_cover_state() is CoverState.NOT_PRESENT:
            raise NotSupportedError(f"{self.calibrator_device} has no cover")

    async def _light_present(self) -> None:
        if await self._hw_get_calibrator_state() is CalibratorState.NOT_PRESENT:
            raise NotSupportedError(f"{self.calibrator_device} has no flat-field light")

    async def _move_cover(self, target: CoverState) -> None:
        await self._cover_present()
        await self._hw_move_cover(target is CoverState.OPEN)
        state = await self._hw_get_cover_state()
        if state is not target:
            raise MoveError(f"{self.calibrator_device}: the cover is {state.value}, not {target.value}")

    async def _switch_light(self, hardware: Awaitable[None], target: CalibratorState) -> None:
        await hardware
        state = await self._hw_get_calibrator_state()
        if state is not target:
            raise CalibratorError(f"{self.calibrator_device}: the light is {state.value}, not {target.value}")

    # --- ICoverCalibrator ----------------------------------------------------------------------

    async def open_cover(self) -> None:
        await self._move_cover(CoverState.OPEN)

    async def close_cover(self) -> None:
        await self._move_cover(CoverState.CLOSED)

    async def halt_cover(self) -> None:
        await self._cover_present()
        await self._hw_halt_cover()

    async def get_cover_state(self) -> CoverState:
        return await self._hw_get_cover_state()

    async def calibrator_on(self, brightness: int) -> None:
        maximum = await self.get_max_brightness()
        if isinstance(brightness, bool) or not isinstance(brightness, int) or not 0 <= brightness <= maximum:
            wanted = f"an integer within 0..{maximum}"
            raise InvalidArgumentError(
                f"{self.calibrator_device}: brightness must be {wanted}, got {brightness!r}"
            )
        await self._switch_light(self._hw_calibrator_on(brightness), CalibratorState.READY)

    async def calibrator_off(self) -> None:
        await self._light_present()
        await self._switch_light(self._hw_calibrator_off(), CalibratorState.OFF)

    async def get_calibrator_state(self) -> CalibratorState:
        return await self._hw_get_calibrator_state()

    async def get_brightness(self) -> int:
        await self._light_present()
        return await self._hw_get_brightness()

    async def get_max_brightness(self) -> int:
        await self._light_present()
        return await self._hw_get_max_brightness()
