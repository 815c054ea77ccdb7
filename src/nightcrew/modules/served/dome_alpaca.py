"""The served dome's Alpaca adapter: a nightcrew roof or dome (IRoof, IDome) as an Alpaca Dome.

Any IRoof module (a roll-off roof or a dome's shutter); an IDome also has an azimuth. The work on
the module is the served dome role's (:mod:`nightcrew.modules.served.dome`), which the INDI dome
shares.
"""

from __future__ import annotations

from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest
from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import IDome, IRoof, MotionStatus
from nightcrew.modules.served.dome import ServedDomeRole

__all__ = ["ServedDome"]

#: ShutterState.
_OPEN, _CLOSED, _OPENING, _CLOSING, _ERROR = range(5)
_SHUTTER = {
    MotionStatus.IDLE: _OPEN,
    MotionStatus.PARKED: _CLOSED,
    MotionStatus.MOVING: _OPENING,
    MotionStatus.INITIALIZING: _OPENING,
    MotionStatus.PARKING: _CLOSING,
}


class ServedDome(ServedDevice):
    """Alpaca Dome (IDomeV3 members) on a nightcrew IRoof module; IDome adds the azimuth."""

    device_type = "dome"
    type_name = "Dome"
    interface_version = 3  # IDomeV3 (Platform 7)
    state_members = ("Altitude", "AtHome", "AtPark", "Azimuth", "ShutterStatus", "Slewing")
    interface = IRoof

    async def _role(self) -> ServedDomeRole:
        return ServedDomeRole(await self.proxy(IRoof))

    async def _dome(self, member: str) -> IDome:
        dome = (await self._role()).dome
        if dome is None:
            raise NotSupportedError(f"{member}: module {self.module} is a roof without azimuth")
        return dome

    async def get_shutterstatus(self, request: AlpacaRequest) -> int:
        self.action.raise_failure()
        return _SHUTTER.get(await (await self._role()).status(), _ERROR)

    async def put_openshutter(self, request: AlpacaRequest) -> None:
        role = await self._role()
        self.action.start("openshutter", role.open)
        await self.action.settle(self.settle_time)

    async def put_closeshutter(self, request: AlpacaRequest) -> None:
        role = await self._role()
        self.action.start("closeshutter", role.close, preempt=True)  # closing always wins
        await self.action.settle(self.settle_time)

    async def put_abortslew(self, request: AlpacaRequest) -> None:
        await (await self._role()).stop()
        await self.action.cancel()

    async def get_cansetshutter(self, request: AlpacaRequest) -> bool:
        return True

    async def get_cansetazimuth(self, request: AlpacaRequest) -> bool:
        return (await self._role()).dome is not None

    async def get_canfindhome(self, request: AlpacaRequest) -> bool:
        return False

    get_canpark = get_cansetpark = get_cansetaltitude = get_cansyncazimuth = get_canslave = get_canfindhome
    get_athome = get_atpark = get_slaved = get_canfindhome

    async def put_slaved(self, request: AlpacaRequest) -> None:
        if request.boolean("Slaved"):
            raise NotSupportedError("slaved: nightcrew domes follow the telescope by their own configuration")

    async def get_slewing(self, request: AlpacaRequest) -> bool:
        self.action.raise_failure()
        return self.action.current == "slewtoazimuth"

    async def get_azimuth(self, request: AlpacaRequest) -> float:
        return await (await self._dome("azimuth")).get_azimuth()

    async def put_slewtoazimuth(self, request: AlpacaRequest) -> None:
        azimuth = request.number("Azimuth")
        if not 0.0 <= azimuth < 360.0:
            raise InvalidArgumentError(f"azimuth must be within 0..360 degrees, got {azimuth}")
        dome = await self._dome("slewtoazimuth")
        self.action.start("slewtoazimuth", lambda: dome.move_azimuth(azimuth))
        await self.action.settle(self.settle_time)
