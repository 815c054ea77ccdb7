"""A flat-field panel and/or dust cap behind an INDI driver: INDI's standard light box properties
(``FLAT_LIGHT_CONTROL``, ``FLAT_LIGHT_INTENSITY``) and dust cap properties (``CAP_PARK``,
``CAP_ABORT``).

What the device has comes from its ``DRIVER_INFO.DRIVER_INTERFACE`` bits (512 dust cap,
1024 light box), defined before the device connects; a part it lacks reports NOT_PRESENT
(``indi_simulator_lightpanel`` is a light without a cover). The brightness range is the
intensity's own limits as the driver defines them.

Example (``examples/indi/calibrator.yaml``)::

    class: nightcrew.modules.indi.IndiCoverCalibrator
    host: 192.168.1.20
    device: Light Panel Simulator
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.indi import IndiError, PropertyState
from nightcrew.errors import CalibratorError, MoveError, NotSupportedError
from nightcrew.interfaces import CalibratorState, CoverState
from nightcrew.modules.calibrator import BaseCoverCalibrator
from nightcrew.modules.indi.link import IndiModule

__all__ = ["IndiCoverCalibrator"]

_DUST_CAP = 512
_LIGHT_BOX = 1024
_CAP = "CAP_PARK"
_CAP_ABORT = "CAP_ABORT"
_LIGHT = "FLAT_LIGHT_CONTROL"
_INTENSITY = "FLAT_LIGHT_INTENSITY"
_VALUE = "FLAT_LIGHT_INTENSITY_VALUE"


class IndiCoverCalibrator(IndiModule, BaseCoverCalibrator):
    """An INDI light box (flat panel) and/or dust cap, e.g. a flip-flat.

    Args:
        **kwargs: INDI options (``host``, ``port``, ``device``, ``connect_timeout``,
            ``move_timeout`` for the cover and the light) and module options.
    """

    indi_needs = ("DRIVER_INFO",)

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._has_cap = False
        self._has_light = False
        self._halted = False  # a halted cover is neither open nor closed, whatever CAP_PARK shows

    @property
    def calibrator_device(self) -> str:
        return self._indi.where

    async def _on_indi_ready(self) -> None:
        # The parts' properties come after the device connects: wait for those it says it has.
        info = self._indi.vector("DRIVER_INFO")
        try:
            interface = int(str(info.members.get("DRIVER_INTERFACE", "0")))
        except ValueError:
            interface = 0
        self._has_cap = bool(interface & _DUST_CAP)
        self._has_light = bool(interface & _LIGHT_BOX)
        if not (self._has_cap or self._has_light):
            raise NotSupportedError(f"{self._indi.where} is neither a dust cap nor a light box")
        needed = ([_CAP] if self._has_cap else []) + ([_LIGHT, _INTENSITY] if self._has_light else [])
        for name in needed:
            await self._indi.client.wait_defined(self._indi.device, name, self._indi.connect_timeout)

    # --- cover ---------------------------------------------------------------------------------

    async def _hw_get_cover_state(self) -> CoverState:
        if not self._has_cap:
            return CoverState.NOT_PRESENT
        vector = self._indi.vector(_CAP)
        if vector.state is PropertyState.BUSY:
            return CoverState.MOVING
        if vector.state is PropertyState.ALERT:
            return CoverState.ERROR
        if self._halted:
            return CoverState.UNKNOWN
        on = vector.on_switches()
        if on == ["PARK"]:
            return CoverState.CLOSED
        if on == ["UNPARK"]:
            return CoverState.OPEN
        return CoverState.UNKNOWN

    async def _hw_move_cover(self, open_: bool) -> None:
        self._halted = False
        member = "UNPARK" if open_ else "PARK"
        try:
            await self._indi.switch(_CAP, member, wait=self._move_timeout)
        except IndiError as exc:
            what = "opening" if open_ else "closing"
            raise MoveError(f"{self._indi.where}: {what} the cover: {exc}") from exc

    async def _hw_halt_cover(self) -> None:
        if not self._indi.has(_CAP_ABORT):
            raise NotSupportedError(f"{self._indi.where} cannot halt its cover (no {_CAP_ABORT})")
        self._halted = self._indi.is_busy(_CAP)  # a cover at rest stays where it is known to be
        await self._indi.abort(_CAP_ABORT)

    # --- light ---------------------------------------------------------------------------------

    async def _hw_get_calibrator_state(self) -> CalibratorState:
        if not self._has_light:
            return CalibratorState.NOT_PRESENT
        control = self._indi.vector(_LIGHT)
        states = (control.state, self._indi.vector(_INTENSITY).state)
        if PropertyState.ALERT in states:
            return CalibratorState.ERROR
        if PropertyState.BUSY in states:
            return CalibratorState.NOT_READY
        on = control.on_switches()
        if on == ["FLAT_LIGHT_ON"]:
            return CalibratorState.READY
        if on == ["FLAT_LIGHT_OFF"]:
            return CalibratorState.OFF
        return CalibratorState.UNKNOWN

    async def _hw_calibrator_on(self, brightness: int) -> None:
        try:
            await self._indi.switch(_LIGHT, "FLAT_LIGHT_ON", wait=self._move_timeout)
            await self._indi.send(
                _INTENSITY,
                {_VALUE: float(brightness)},
                wait=self._move_timeout,
                done=lambda v: round(v.number(_VALUE)) == brightness,
            )
        except IndiError as exc:
            raise CalibratorError(f"{self._indi.where}: switching the light on: {exc}") from exc

    async def _hw_calibrator_off(self) -> None:
        try:
            await self._indi.switch(_LIGHT, "FLAT_LIGHT_OFF", wait=self._move_timeout)
        except IndiError as exc:
            raise CalibratorError(f"{self._indi.where}: switching the light off: {exc}") from exc

    async def _hw_get_brightness(self) -> int:
        if self._indi.vector(_LIGHT).on_switches() != ["FLAT_LIGHT_ON"]:
            return 0
        return round(self._indi.vector(_INTENSITY).number(_VALUE))

    async def _hw_get_max_brightness(self) -> int:
        _, maximum, _ = self._indi.vector(_INTENSITY).limits.get(_VALUE, (0.0, 0.0, 0.0))
        return int(maximum)
