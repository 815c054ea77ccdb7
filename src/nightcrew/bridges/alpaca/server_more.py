"""Rotators, switches and cover calibrators served as Alpaca devices.

* Rotator: positions are the module's sky position angle, MechanicalPosition its mechanical angle
  (degrees); Move, MoveAbsolute and MoveMechanical run in the background with IsMoving true.
* Switch: the module's switches by index (Alpaca's ``Id``); their names, ranges and steps come
  from ``get_switches()``. Switches are set synchronously (CanAsync is false).
* CoverCalibrator: the cover and the light of an ICoverCalibrator module; OpenCover, CloseCover,
  CalibratorOn and CalibratorOff run in the background (CoverMoving, CalibratorChanging).
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import (
    CalibratorState,
    CoverState,
    ICoverCalibrator,
    IRotator,
    ISwitch,
    MotionStatus,
    SwitchInfo,
)

__all__ = ["ServedCoverCalibrator", "ServedRotator", "ServedSwitch"]


def _angle(request: AlpacaRequest, name: str) -> float:
    angle = request.number(name)
    if not 0.0 <= angle < 360.0:
        raise InvalidArgumentError(f"{name.lower()} must be within 0..360 degrees, got {angle}")
    return angle


class ServedRotator(ServedDevice):
    """Alpaca Rotator (IRotatorV4) on a nightcrew IRotator module."""

    device_type = "rotator"
    type_name = "Rotator"
    interface_version = 4
    state_members = ("IsMoving", "MechanicalPosition", "Position")
    interface = IRotator

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._target: float | None = None

    async def _rotator(self) -> IRotator:
        return await self.proxy(IRotator)

    async def get_canreverse(self, request: AlpacaRequest) -> bool:
        return True

    async def get_reverse(self, request: AlpacaRequest) -> bool:
        return await (await self._rotator()).get_rotator_reversed()

    async def put_reverse(self, request: AlpacaRequest) -> None:
        await (await self._rotator()).set_rotator_reversed(request.boolean("Reverse"))

    async def get_position(self, request: AlpacaRequest) -> float:
        return await (await self._rotator()).get_position_angle()

    async def get_mechanicalposition(self, request: AlpacaRequest) -> float:
        return await (await self._rotator()).get_mechanical_angle()

    async def get_targetposition(self, request: AlpacaRequest) -> float:
        return self._target if self._target is not None else await self.get_position(request)

    async def get_ismoving(self, request: AlpacaRequest) -> bool:
        self.action.raise_failure()
        status = await (await self._rotator()).get_motion_status()
        return self.action.running or status is MotionStatus.MOVING

    async def put_move(self, request: AlpacaRequest) -> None:
        delta = request.number("Position")
        rotator = await self._rotator()
        self._target = (await rotator.get_position_angle() + delta) % 360.0
        self.action.start("move", lambda: rotator.move_position_angle_by(delta))
        await self.action.settle(self.settle_time)

    async def put_moveabsolute(self, request: AlpacaRequest) -> None:
        angle = _angle(request, "Position")
        rotator = await self._rotator()
        self._target = angle
        self.action.start("moveabsolute", lambda: rotator.move_position_angle(angle))
        await self.action.settle(self.settle_time)

    async def put_movemechanical(self, request: AlpacaRequest) -> None:
        angle = _angle(request, "Position")
        rotator = await self._rotator()
        self.action.start("movemechanical", lambda: rotator.move_mechanical(angle))
        await self.action.settle(self.settle_time)

    async def put_halt(self, request: AlpacaRequest) -> None:
        await (await self._rotator()).stop_motion()
        await self.action.cancel()


class ServedSwitch(ServedDevice):
    """Alpaca Switch (ISwitchV3, without asynchronous switching) on a nightcrew ISwitch module."""

    device_type = "switch"
    type_name = "Switch"
    interface_version = 3
    interface = ISwitch

    async def _switch(self) -> ISwitch:
        return await self.proxy(ISwitch)

    async def _info(self, request: AlpacaRequest) -> SwitchInfo:
        """The switch the request's ``Id`` names; InvalidValue for one the device does not have."""
        index = request.integer("Id")
        switches = await (await self._switch()).get_switches()
        if not 0 <= index < len(switches):
            raise InvalidArgumentError(f"id must be within 0..{len(switches) - 1}, got {index}")
        return switches[index]

    async def get_maxswitch(self, request: AlpacaRequest) -> int:
        return len(await (await self._switch()).get_switches())

    async def get_canwrite(self, request: AlpacaRequest) -> bool:
        return (await self._info(request)).can_write

    async def get_canasync(self, request: AlpacaRequest) -> bool:
        await self._info(request)
        return False

    async def get_getswitchname(self, request: AlpacaRequest) -> str:
        return (await self._info(request)).name

    async def get_getswitchdescription(self, request: AlpacaRequest) -> str:
        return (await self._info(request)).description

    async def get_minswitchvalue(self, request: AlpacaRequest) -> float:
        return (await self._info(request)).min_value

    async def get_maxswitchvalue(self, request: AlpacaRequest) -> float:
        return (await self._info(request)).max_value

    async def get_switchstep(self, request: AlpacaRequest) -> float:
        return (await self._info(request)).step

    async def get_statechangecomplete(self, request: AlpacaRequest) -> bool:
        await self._info(request)
        return True  # switches are set synchronously: every change is complete when it returns

    async def get_getswitch(self, request: AlpacaRequest) -> bool:
        info = await self._info(request)
        return await (await self._switch()).get_switch(info.index)

    async def get_getswitchvalue(self, request: AlpacaRequest) -> float:
        info = await self._info(request)
        return await (await self._switch()).get_switch_value(info.index)

    async def put_setswitch(self, request: AlpacaRequest) -> None:
        info = await self._info(request)
        await (await self._switch()).set_switch(info.index, request.boolean("State"))

    async def put_setswitchvalue(self, request: AlpacaRequest) -> None:
        info = await self._info(request)
        await (await self._switch()).set_switch_value(info.index, request.number("Value"))

    async def get_devicestate(self, request: AlpacaRequest) -> list[dict[str, Any]]:
        """Switch's DeviceState: every switch's state and value (named with its Id)."""
        switch = await self._switch()
        state: list[dict[str, Any]] = []
        for info in await switch.get_switches():
            state.append({"Name": f"GetSwitch{info.index}", "Value": await switch.get_switch(info.index)})
            value = await switch.get_switch_value(info.index)
            state.append({"Name": f"GetSwitchValue{info.index}", "Value": value})
            state.append({"Name": f"StateChangeComplete{info.index}", "Value": True})
        state.append(self.time_stamp())
        return state


#: CoverStatus and CalibratorStatus of the Alpaca API.
_COVER = {
    CoverState.NOT_PRESENT: 0,
    CoverState.CLOSED: 1,
    CoverState.MOVING: 2,
    CoverState.OPEN: 3,
    CoverState.UNKNOWN: 4,
    CoverState.ERROR: 5,
}
_CALIBRATOR = {
    CalibratorState.NOT_PRESENT: 0,
    CalibratorState.OFF: 1,
    CalibratorState.NOT_READY: 2,
    CalibratorState.READY: 3,
    CalibratorState.UNKNOWN: 4,
    CalibratorState.ERROR: 5,
}
_COVER_MOTIONS = ("opencover", "closecover")
_CALIBRATOR_CHANGES = ("calibratoron", "calibratoroff")


class ServedCoverCalibrator(ServedDevice):
    """Alpaca CoverCalibrator (ICoverCalibratorV2) on a nightcrew ICoverCalibrator module."""

    device_type = "covercalibrator"
    type_name = "CoverCalibrator"
    interface_version = 2
    state_members = ("Brightness", "CalibratorState", "CoverState", "CalibratorChanging", "CoverMoving")
    interface = ICoverCalibrator

    async def _device(self) -> ICoverCalibrator:
        return await self.proxy(ICoverCalibrator)

    async def get_coverstate(self, request: AlpacaRequest) -> int:
        self.action.raise_failure()
        if self.action.current in _COVER_MOTIONS:
            return _COVER[CoverState.MOVING]
        return _COVER[await (await self._device()).get_cover_state()]

    async def get_covermoving(self, request: AlpacaRequest) -> bool:
        return await self.get_coverstate(request) == _COVER[CoverState.MOVING]

    async def get_calibratorstate(self, request: AlpacaRequest) -> int:
        self.action.raise_failure()
        if self.action.current in _CALIBRATOR_CHANGES:
            return _CALIBRATOR[CalibratorState.NOT_READY]
        return _CALIBRATOR[await (await self._device()).get_calibrator_state()]

    async def get_calibratorchanging(self, request: AlpacaRequest) -> bool:
        return await self.get_calibratorstate(request) == _CALIBRATOR[CalibratorState.NOT_READY]

    async def get_brightness(self, request: AlpacaRequest) -> int:
        return await (await self._device()).get_brightness()

    async def get_maxbrightness(self, request: AlpacaRequest) -> int:
        return await (await self._device()).get_max_brightness()

    async def put_opencover(self, request: AlpacaRequest) -> None:
        device = await self._device()
        self.action.start("opencover", device.open_cover)
        await self.action.settle(self.settle_time)

    async def put_closecover(self, request: AlpacaRequest) -> None:
        device = await self._device()
        self.action.start("closecover", device.close_cover)
        await self.action.settle(self.settle_time)

    async def put_haltcover(self, request: AlpacaRequest) -> None:
        await (await self._device()).halt_cover()
        if self.action.current in _COVER_MOTIONS:
            await self.action.cancel()

    async def put_calibratoron(self, request: AlpacaRequest) -> None:
        brightness = request.integer("Brightness")
        device = await self._device()
        maximum = await device.get_max_brightness()
        if not 0 <= brightness <= maximum:
            raise InvalidArgumentError(f"brightness must be within 0..{maximum}, got {brightness}")
        self.action.start("calibratoron", lambda: device.calibrator_on(brightness))
        await self.action.settle(self.settle_time)

    async def put_calibratoroff(self, request: AlpacaRequest) -> None:
        device = await self._device()
        self.action.start("calibratoroff", device.calibrator_off)
        await self.action.settle(self.settle_time)
