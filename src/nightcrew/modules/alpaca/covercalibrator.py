"""A telescope cover and flat-field light on an Alpaca CoverCalibrator device.

``OpenCover``/``CloseCover`` start the cover, ``CoverState`` is polled until it stops moving;
``CalibratorOn``/``CalibratorOff`` switch the light, ``CalibratorState`` is polled until it is no
longer NotReady (warming up). ASCOM numbers both states 0 NotPresent, 1 Closed/Off, 2 Moving/
NotReady, 3 Open/Ready, 4 Unknown, 5 Error. :class:`BaseCoverCalibrator` refuses parts the device
lacks and checks where each part ended up.

Example (``examples/alpaca/covercalibrator.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaCoverCalibrator
    server: http://127.0.0.1:11111
    device_number: 0
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import StrEnum
from typing import Any, Generic, TypeVar

from nightcrew.errors import CalibratorError, MoveError, NightcrewError
from nightcrew.interfaces import CalibratorState, CoverState
from nightcrew.modules.alpaca.checked import CheckedGets
from nightcrew.modules.calibrator import BaseCoverCalibrator

__all__ = ["AlpacaCoverCalibrator"]

S = TypeVar("S", bound=StrEnum)


@dataclass(frozen=True)
class _Part(Generic[S]):
    """The cover or the light: its state member, its states in ASCOM order, its moving state."""

    member: str
    states: list[S]
    moving: S


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
    CoverState.MOVING,
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
    CalibratorState.NOT_READY,
)


class AlpacaCoverCalibrator(CheckedGets, BaseCoverCalibrator):
    """A cover and/or flat-field panel on an Alpaca server.

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

    @property
    def calibrator_device(self) -> str:
        return self.device.name

    async def _part_state(self, part: _Part[S]) -> S:
        value = await self._get_integer(part.member)
        if not 0 <= value < len(part.states):
            raise self._bad_value(part.member, value, "an ASCOM state (0..5)")
        return part.states[value]

    async def _drive(
        self, part: _Part[S], method: str, within: float, error: type[NightcrewError], **params: Any
    ) -> None:
        """``PUT method`` and wait until the part has left its moving state."""
        await self._put(method, **params)
        moving = part.states.index(part.moving)
        await self._poll_until(part.member, lambda value: value != moving, within, method, error)

    async def _hw_get_cover_state(self) -> CoverState:
        return await self._part_state(_COVER)

    async def _hw_move_cover(self, open_: bool) -> None:
        await self._drive(_COVER, "opencover" if open_ else "closecover", self._cover_timeout, MoveError)

    async def _hw_halt_cover(self) -> None:
        await self._put("haltcover")

    async def _hw_get_calibrator_state(self) -> CalibratorState:
        return await self._part_state(_LIGHT)

    async def _hw_calibrator_on(self, brightness: int) -> None:
        await self._drive(
            _LIGHT, "calibratoron", self._calibrator_timeout, CalibratorError, Brightness=brightness
        )

    async def _hw_calibrator_off(self) -> None:
        await self._drive(_LIGHT, "calibratoroff", self._calibrator_timeout, CalibratorError)

    async def _hw_get_brightness(self) -> int:
        return await self._get_integer("brightness")

    async def _hw_get_max_brightness(self) -> int:
        return await self._get_integer("maxbrightness")
