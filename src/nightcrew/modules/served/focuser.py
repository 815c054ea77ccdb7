"""The served focuser: what Alpaca and INDI clients ask of a nightcrew IFocuser, written once.

Clients count a focuser's position in whole steps, nightcrew in millimetres: the role converts
with the steps of its adapter (Alpaca: the server's ``focuser_step``; INDI: one micrometre). The
position is the focuser's base focus (without the filter/model offset). The temperature is the
first the module reports (ITemperatures).
"""

from __future__ import annotations

from nightcrew.interfaces import IFocuser, ITemperatures, MotionStatus

__all__ = ["ServedFocuserRole"]


class ServedFocuserRole:
    """The IFocuser module behind a served focuser.

    Args:
        focuser: The module's proxy (ITemperatures is checked on it).
        steps_per_mm: Client steps per millimetre of focus.
    """

    def __init__(self, focuser: IFocuser, steps_per_mm: float) -> None:
        self.focuser = focuser
        self.steps_per_mm = steps_per_mm

    async def position(self) -> float:
        """The focus in steps (not rounded: each protocol rounds its own way)."""
        return await self.focuser.get_focus() * self.steps_per_mm

    async def move(self, steps: float) -> None:
        await self.focuser.set_focus(steps / self.steps_per_mm)

    async def status(self) -> MotionStatus:
        return await self.focuser.get_motion_status()

    async def stop(self) -> None:
        await self.focuser.stop_motion()

    @property
    def has_temperature(self) -> bool:
        return isinstance(self.focuser, ITemperatures)

    async def temperature(self) -> float | None:
        """The first temperature the module reports, °C; None if it reports none."""
        if not isinstance(self.focuser, ITemperatures):
            return None
        temperatures = await self.focuser.get_temperatures()
        return next(iter(temperatures.values())) if temperatures else None
