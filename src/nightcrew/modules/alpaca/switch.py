"""Switches (power outlets, relays, dew heaters, dimmers) on an Alpaca Switch device.

At every (re)connect the module reads ``MaxSwitch`` and each switch's name, description,
``CanWrite``, ``MinSwitchValue``, ``MaxSwitchValue`` and ``SwitchStep``; calls are checked against
that list before they reach the device, so a wrong switch number or value is refused naming the
switch and its range.

Example (``examples/alpaca/switch.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaSwitch
    server: http://127.0.0.1:11111
    device_number: 0
"""

from __future__ import annotations

import math
from typing import Any

from nightcrew.bridges.alpaca.errors import AlpacaReplyError
from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import ISwitch, SwitchInfo
from nightcrew.modules.alpaca.device import AlpacaModule

__all__ = ["AlpacaSwitch"]

#: How far (in steps) a value may be from a multiple of the step: float noise, not a wrong value.
_STEP_TOLERANCE = 1e-6


class AlpacaSwitch(AlpacaModule, ISwitch):
    """The switches of an Alpaca Switch device.

    Args:
        **kwargs: Alpaca options (``server``, ``device_number``, ...) and module options.
    """

    device_type = "switch"

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._switches: list[SwitchInfo] = []

    async def _on_connected(self) -> None:
        await super()._on_connected()
        count = await self._get("maxswitch")
        if isinstance(count, bool) or not isinstance(count, int) or count < 0:
            raise AlpacaReplyError(
                f"{self.device.name}: GET maxswitch: {count!r} is not a number of switches"
            )
        self._switches = [await self._read_info(index) for index in range(count)]

    async def _read_info(self, index: int) -> SwitchInfo:
        return SwitchInfo(
            index=index,
            name=str(await self._get("getswitchname", Id=index)),
            description=str(await self._get("getswitchdescription", Id=index)),
            can_write=bool(await self._get("canwrite", Id=index)),
            min_value=float(await self._get("minswitchvalue", Id=index)),
            max_value=float(await self._get("maxswitchvalue", Id=index)),
            step=float(await self._get("switchstep", Id=index)),
        )

    def _info(self, switch: int) -> SwitchInfo:
        if not 0 <= switch < len(self._switches):
            raise InvalidArgumentError(
                f"{self.device.name} has switches 0..{len(self._switches) - 1}, not {switch}"
                if self._switches
                else f"{self.device.name} has no switches"
            )
        return self._switches[switch]

    def _writable(self, switch: int) -> SwitchInfo:
        info = self._info(switch)
        if not info.can_write:
            raise NotSupportedError(f"{self.device.name}: switch {switch} ({info.name!r}) is read-only")
        return info

    # --- ISwitch -------------------------------------------------------------------------------

    async def get_switches(self) -> list[SwitchInfo]:
        return list(self._switches)

    async def get_switch(self, switch: int) -> bool:
        self._info(switch)
        return bool(await self._get("getswitch", Id=switch))

    async def set_switch(self, switch: int, state: bool) -> None:
        self._writable(switch)
        await self._put("setswitch", Id=switch, State=bool(state))

    async def get_switch_value(self, switch: int) -> float:
        self._info(switch)
        return float(await self._get("getswitchvalue", Id=switch))

    async def set_switch_value(self, switch: int, value: float) -> None:
        info = self._writable(switch)
        where = f"{self.device.name}: switch {switch} ({info.name!r})"
        if not (math.isfinite(value) and info.min_value <= value <= info.max_value):
            raise InvalidArgumentError(f"{where}: {value} is outside {info.min_value:g}..{info.max_value:g}")
        if info.step > 0:
            steps = (value - info.min_value) / info.step
            if abs(steps - round(steps)) > _STEP_TOLERANCE:
                raise InvalidArgumentError(
                    f"{where}: {value} is not {info.min_value:g} plus a multiple of the step {info.step:g}"
                )
        await self._put("setswitchvalue", Id=switch, Value=float(value))
