"""The served focuser's Alpaca adapter: a nightcrew focuser (IFocuser) as an Alpaca Focuser.

nightcrew focus positions are millimetres, Alpaca's are whole steps; the server's ``focuser_step``
(mm per step) converts, ``focuser_max_step`` is the largest position. The work on the module is
the served focuser role's (:mod:`nightcrew.modules.served.focuser`), which the INDI focuser shares.
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest
from nightcrew.errors import ConfigError, InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import IFocuser, MotionStatus
from nightcrew.modules.served.focuser import ServedFocuserRole

__all__ = ["ServedFocuser"]


class ServedFocuser(ServedDevice):
    """Alpaca Focuser (IFocuserV4 members) on a nightcrew IFocuser module.

    Args:
        step: Millimetres per Alpaca step (> 0).
        max_step: Largest Alpaca position (> 0).
    """

    device_type = "focuser"
    type_name = "Focuser"
    interface_version = 4  # IFocuserV4 (Platform 7)
    state_members = ("IsMoving", "Position", "Temperature")
    interface = IFocuser

    def __init__(self, *args: Any, step: float = 0.001, max_step: int = 100_000, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        if not step > 0:
            raise ConfigError(f"must be > 0 mm, got {step}", key="focuser_step")
        if not max_step > 0:
            raise ConfigError(f"must be > 0 steps, got {max_step}", key="focuser_max_step")
        self._step, self._max_step = float(step), int(max_step)

    async def _role(self) -> ServedFocuserRole:
        return ServedFocuserRole(await self.proxy(IFocuser), 1.0 / self._step)

    async def get_absolute(self, request: AlpacaRequest) -> bool:
        return True

    async def get_maxstep(self, request: AlpacaRequest) -> int:
        return self._max_step

    get_maxincrement = get_maxstep

    async def get_stepsize(self, request: AlpacaRequest) -> float:
        return self._step * 1000.0  # microns

    async def get_position(self, request: AlpacaRequest) -> int:
        return round(await (await self._role()).position())

    async def get_ismoving(self, request: AlpacaRequest) -> bool:
        self.action.raise_failure()
        status = await (await self._role()).status()
        return self.action.running or status is MotionStatus.MOVING

    async def put_move(self, request: AlpacaRequest) -> None:
        position = request.integer("Position")
        if not 0 <= position <= self._max_step:
            raise InvalidArgumentError(f"position must be within 0..{self._max_step}, got {position}")
        role = await self._role()
        self.action.start("move", lambda: role.move(position))
        await self.action.settle(self.settle_time)

    async def put_halt(self, request: AlpacaRequest) -> None:
        await (await self._role()).stop()
        await self.action.cancel()

    async def get_tempcompavailable(self, request: AlpacaRequest) -> bool:
        return False

    get_tempcomp = get_tempcompavailable

    async def put_tempcomp(self, request: AlpacaRequest) -> None:
        if request.boolean("TempComp"):
            raise NotSupportedError("tempcomp: this focuser has no temperature compensation")

    async def get_temperature(self, request: AlpacaRequest) -> float:
        temperature = await (await self._role()).temperature()
        if temperature is None:
            raise NotSupportedError(f"temperature: module {self.module} reports no temperature")
        return temperature
