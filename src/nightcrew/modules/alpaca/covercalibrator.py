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

from enum import StrEnum
from typing import Any, TypeVar

from nightcrew.bridges.alpaca.errors import AlpacaReplyError
from nightcrew.errors import ConfigError, InvalidArgumentError, MoveError, NotSupportedError, RemoteError
from nightcrew.interfaces import CalibratorState, CoverState, ICoverCalibrator
from nightcrew.modules.alpaca.device import AlpacaModule

__all__ = ["AlpacaCoverCalibrator"]

S = TypeVar("S", bound=StrEnum)

#: ASCOM CoverStatus and CalibratorStatus numbers, in order.
_COVER_STATES = [
    CoverState.NOT_PRESENT,
    CoverState.CLOSED,
    CoverState.MOVING,
    CoverState.OPEN,
    CoverState.UNKNOWN,
    CoverState.ERROR,
]
_CALIBRATOR_STATES = [
    CalibratorState.NOT_PRESENT,
    CalibratorState.OFF,
    CalibratorState.NOT_READY,
    CalibratorState.READY,
    CalibratorState.UNKNOWN,
    CalibratorState.ERROR,
]


class AlpacaCoverCalibrator(AlpacaModule, ICoverCalibrator):
    """A cover and/or flat-field panel.

    Args:
        cover_timeout: Wall seconds opening or closing the cover may take (below the interface's 120 s).
        calibrator_timeout: Wall seconds the light may take to become stable or go off (below 60 s).
        **kwargs: Alpaca options (``server``, ``device_number``, ...) and module options.
    """

    device_type = "covercalibrator"

    def __init__(
        self, *, cover_timeout: float = 100.0, calibrator_timeout: float = 50.0, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        if not 0 < cover_timeout < 120:
            raise ConfigError(f"must be within 0..120 seconds, got {cover_timeout}", key="cover_timeout")
        if not 0 < calibrator_timeout < 60:
            raise ConfigError(
                f"must be within 0..60 seconds, got {calibrator_timeout}", key="calibrator_timeout"
            )
        self._cover_timeout = float(cover_timeout)
        self._calibrator_timeout = float(calibrator_timeout)

    def _ascom_state(self, value: Any, states: list[S], member: str) -> S:
        if isinstance(value, bool) or not isinstance(value, int) or not 0 <= value < len(states):
            raise AlpacaReplyError(
                f"{self.device.name}: GET {member}: {value!r} is not an ASCOM state (0..5)"
            )
        return states[value]

    async def _present(self, member: str, states: list[S], part: str) -> None:
        if self._ascom_state(await self._get(member), states, member) is states[0]:
            raise NotSupportedError(f"{self.device.name} has no {part} ({member} NotPresent)")

    # --- cover ---------------------------------------------------------------------------------

    async def _move_cover(self, method: str, target: CoverState) -> None:
        await self._present("coverstate", _COVER_STATES, "cover")
        await self._put(method)
        arrived = await self._poll_until(
            "coverstate",
            lambda value: value != _COVER_STATES.index(CoverState.MOVING),
            self._cover_timeout,
            method,
            MoveError,
        )
        state = self._ascom_state(arrived, _COVER_STATES, "coverstate")
        if state is not target:
            raise MoveError(f"{self.device.name}: {method}: the cover is {state.value}, not {target.value}")

    async def open_cover(self) -> None:
        await self._move_cover("opencover", CoverState.OPEN)

    async def close_cover(self) -> None:
        await self._move_cover("closecover", CoverState.CLOSED)

    async def halt_cover(self) -> None:
        await self._present("coverstate", _COVER_STATES, "cover")
        await self._put("haltcover")

    async def get_cover_state(self) -> CoverState:
        return self._ascom_state(await self._get("coverstate"), _COVER_STATES, "coverstate")

    # --- calibrator ----------------------------------------------------------------------------

    async def _switch_light(self, method: str, target: CalibratorState, **params: Any) -> None:
        await self._put(method, **params)
        arrived = await self._poll_until(
            "calibratorstate",
            lambda value: value != _CALIBRATOR_STATES.index(CalibratorState.NOT_READY),
            self._calibrator_timeout,
            method,
            RemoteError,
        )
        state = self._ascom_state(arrived, _CALIBRATOR_STATES, "calibratorstate")
        if state is not target:
            raise RemoteError(f"{self.device.name}: {method}: the light is {state.value}, not {target.value}")

    async def calibrator_on(self, brightness: int) -> None:
        await self._present("calibratorstate", _CALIBRATOR_STATES, "flat-field light")
        maximum = await self.get_max_brightness()
        if isinstance(brightness, bool) or not isinstance(brightness, int) or not 0 <= brightness <= maximum:
            raise InvalidArgumentError(
                f"{self.device.name}: brightness must be an integer within 0..{maximum}, got {brightness!r}"
            )
        await self._switch_light("calibratoron", CalibratorState.READY, Brightness=brightness)

    async def calibrator_off(self) -> None:
        await self._present("calibratorstate", _CALIBRATOR_STATES, "flat-field light")
        await self._switch_light("calibratoroff", CalibratorState.OFF)

    async def get_calibrator_state(self) -> CalibratorState:
        return self._ascom_state(await self._get("calibratorstate"), _CALIBRATOR_STATES, "calibratorstate")

    async def get_brightness(self) -> int:
        await self._present("calibratorstate", _CALIBRATOR_STATES, "flat-field light")
        return int(await self._get("brightness"))

    async def get_max_brightness(self) -> int:
        await self._present("calibratorstate", _CALIBRATOR_STATES, "flat-field light")
        return int(await self._get("maxbrightness"))
