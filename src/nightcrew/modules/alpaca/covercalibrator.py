"""A telescope cover and flat-field light on an Alpaca CoverCalibrator device.

``OpenCover``/``CloseCover`` start the cover, ``CoverState`` is polled until it arrives;
``CalibratorOn``/``CalibratorOff`` switch the light, ``CalibratorState`` is polled until it is
Ready (stable, take flats now) or Off. ASCOM numbers both states 0 NotPresent, 1 Closed/Off,
2 Moving/NotReady, 3 Open/Ready, 4 Unknown, 5 Error. A part the device lacks (NotPresent) is
refused with NotSupportedError before a call reaches the device.

Example (``examples/alpaca/covercalibrator.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaCoverCalibrator
    server: http://127.0.0.1:11111
    device_number: 0
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import Any, Generic, TypeVar

from nightcrew.errors import (
    InvalidArgumentError,
    MoveError,
    NightcrewError,
    NotSupportedError,
    RemoteError,
)
from nightcrew.interfaces import CalibratorState, CoverState, ICoverCalibrator
from nightcrew.modules.alpaca.checked import CheckedGets

__all__ = ["AlpacaCoverCalibrator"]

S = TypeVar("S", bound=StrEnum)


@dataclass(frozen=True)
class _Part(Generic[S]):
    """The cover or the light: its state member, its states in ASCOM order, and how it fails."""

    member: str
    states: list[S]
    name: str
    moving: S
    error: type[NightcrewError]

    @property
    def not_present(self) -> S:
        return self.states[0]


#: ASCOM CoverStatus and CalibratorStatus, numbered 0..5 in this order.
_COVER = _Part(
    "coverstate",
    [
        CoverState.NOT_PRESENT,
        CoverState.CLOSED,
        CoverState.MOVING,
        CoverState.OPEN,
        CoverState.UNKNOWN,
        CoverState.ERROR,
    ],
    "cover",
    CoverState.MOVING,
    MoveError,
)
_LIGHT = _Part(
    "calibratorstate",
    [
        CalibratorState.NOT_PRESENT,
        CalibratorState.OFF,
        CalibratorState.NOT_READY,
        CalibratorState.READY,
        CalibratorState.UNKNOWN,
        CalibratorState.ERROR,
    ],
    "flat-field light",
    CalibratorState.NOT_READY,
    RemoteError,
)


class AlpacaCoverCalibrator(CheckedGets, ICoverCalibrator):
    """A cover and/or flat-field panel.

    Args:
        cover_timeout: Wall seconds opening or closing the cover may take (below the interface's 120 s).
        calibrator_timeout: Wall seconds the light may take to become stable or go off (below 60 s).
        **kwargs: Alpaca options (``server``, ``device_number``, ...) and module options.
    """

    device_type = "covercalibrator"
    wait_limits = {"cover_timeout": 120.0, "calibrator_timeout": 60.0}

    def __init__(
        self, *, cover_timeout: float = 100.0, calibrator_timeout: float = 50.0, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        self._cover_timeout = self._checked_wait("cover_timeout", cover_timeout)
        self._calibrator_timeout = self._checked_wait("calibrator_timeout", calibrator_timeout)

    async def _part_state(self, part: _Part[S]) -> S:
        value = await self._get_integer(part.member)
        if not 0 <= value < len(part.states):
            raise self._bad_value(part.member, value, "an ASCOM state (0..5)")
        return part.states[value]

    async def _present(self, part: _Part[S]) -> None:
        if await self._part_state(part) is part.not_present:
            raise NotSupportedError(f"{self.device.name} has no {part.name} ({part.member} NotPresent)")

    async def _drive(self, part: _Part[S], method: str, target: S, within: float, **params: Any) -> None:
        """``PUT method`` and wait until the part has left its moving state; it must be at ``target``."""
        await self._put(method, **params)
        moving = part.states.index(part.moving)
        await self._poll_until(part.member, lambda value: value != moving, within, method, part.error)
        state = await self._part_state(part)
        if state is not target:
            raise part.error(
                f"{self.device.name}: {method}: the {part.name} is {state.value}, not {target.value}"
            )

    # --- cover ---------------------------------------------------------------------------------

    async def open_cover(self) -> None:
        await self._present(_COVER)
        await self._drive(_COVER, "opencover", CoverState.OPEN, self._cover_timeout)

    async def close_cover(self) -> None:
        await self._present(_COVER)
        await self._drive(_COVER, "closecover", CoverState.CLOSED, self._cover_timeout)

    async def halt_cover(self) -> None:
        await self._present(_COVER)
        await self._put("haltcover")

    async def get_cover_state(self) -> CoverState:
        return await self._part_state(_COVER)

    # --- calibrator ----------------------------------------------------------------------------

    async def calibrator_on(self, brightness: int) -> None:
        maximum = await self.get_max_brightness()
        if isinstance(brightness, bool) or not isinstance(brightness, int) or not 0 <= brightness <= maximum:
            raise InvalidArgumentError(
                f"{self.device.name}: brightness must be an integer within 0..{maximum}, got {brightness!r}"
            )
        await self._drive(
            _LIGHT, "calibratoron", CalibratorState.READY, self._calibrator_timeout, Brightness=brightness
        )

    async def calibrator_off(self) -> None:
        await self._present(_LIGHT)
        await self._drive(_LIGHT, "calibratoroff", CalibratorState.OFF, self._calibrator_timeout)

    async def get_calibrator_state(self) -> CalibratorState:
        return await self._part_state(_LIGHT)

    async def get_brightness(self) -> int:
        await self._present(_LIGHT)
        return await self._get_integer("brightness")

    async def get_max_brightness(self) -> int:
        await self._present(_LIGHT)
        return await self._get_integer("maxbrightness")
