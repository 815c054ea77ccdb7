"""The served filter wheel's Alpaca adapter: a nightcrew filter wheel (IFilters) as an Alpaca FilterWheel.

Positions are indices into the module's filter list; -1 while the wheel turns. The work on the
module is the served filter wheel role's (:mod:`nightcrew.modules.served.filterwheel`), which the
INDI filter wheel shares.
"""

from __future__ import annotations

from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import IFilters, MotionStatus
from nightcrew.modules.served.filterwheel import ServedFilterWheelRole

__all__ = ["ServedFilterWheel"]


class ServedFilterWheel(ServedDevice):
    """Alpaca FilterWheel (IFilterWheelV3 members) on a nightcrew IFilters module."""

    device_type = "filterwheel"
    type_name = "FilterWheel"
    interface_version = 3  # IFilterWheelV3 (Platform 7)
    state_members = ("Position",)
    interface = IFilters

    async def _role(self) -> ServedFilterWheelRole:
        return ServedFilterWheelRole(await self.proxy(IFilters))

    async def get_names(self, request: AlpacaRequest) -> list[str]:
        return await (await self._role()).names()

    async def get_focusoffsets(self, request: AlpacaRequest) -> list[int]:
        return [0] * len(await self.get_names(request))

    async def get_position(self, request: AlpacaRequest) -> int:
        self.action.raise_failure()
        role = await self._role()
        if self.action.running or await role.status() is MotionStatus.MOVING:
            return -1
        index = await role.index(await role.names())
        return -1 if index is None else index

    async def put_position(self, request: AlpacaRequest) -> None:
        position = request.integer("Position")
        role = await self._role()
        names = await role.names()
        if not 0 <= position < len(names):
            raise InvalidArgumentError(f"position must be within 0..{len(names) - 1}, got {position}")
        self.action.start("position", lambda: role.select(names, position))
        await self.action.settle(self.settle_time)
