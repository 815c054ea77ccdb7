"""Switches (power outlets, relays, dew heaters, dimmers) on an Alpaca Switch device.

At every (re)connect the module reads ``MaxSwitch`` and each switch's name, description,
``CanWrite``, ``MinSwitchValue``, ``MaxSwitchValue`` and ``SwitchStep``; :class:`BaseSwitch`
checks calls against that list before they reach the device.

Example (``examples/alpaca/switch.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaSwitch
    server: http://127.0.0.1:11111
    device_number: 0
"""

from __future__ import annotations

from nightcrew.interfaces import SwitchInfo
from nightcrew.modules.alpaca.checked import CheckedGets
from nightcrew.modules.switch import BaseSwitch

__all__ = ["AlpacaSwitch"]


class AlpacaSwitch(CheckedGets, BaseSwitch):
    """The switches of an Alpaca Switch device.

    Args:
        **kwargs: Alpaca options (``server``, ``device_number``, ...) and module options.
    """

    device_type = "switch"

    @property
    def switch_device(self) -> str:
        return self.device.name

    async def _on_connected(self) -> None:
        await super()._on_connected()
        count = await self._get_integer("maxswitch")
        if count < 0:
            raise self._bad_value("maxswitch", count, "a number of switches")
        self._switches = [await self._read_info(index) for index in range(count)]

    async def _read_info(self, index: int) -> SwitchInfo:
        return SwitchInfo(
            index=index,
            name=await self._get_text("getswitchname", Id=index),
            description=await self._get_text("getswitchdescription", Id=index),
            can_write=await self._get_flag("canwrite", Id=index),
            min_value=await self._get_number("minswitchvalue", Id=index),
            max_value=await self._get_number("maxswitchvalue", Id=index),
            step=await self._get_number("switchstep", Id=index),
        )

    async def _hw_get_value(self, switch: int) -> float:
        return await self._get_number("getswitchvalue", Id=switch)

    async def _hw_set_value(self, switch: int, value: float) -> None:
        await self._put("setswitchvalue", Id=switch, Value=value)

    async def _hw_get_state(self, switch: int) -> bool:
        return await self._get_flag("getswitch", Id=switch)

    async def _hw_set_state(self, switch: int, state: bool) -> None:
        await self._put("setswitch", Id=switch, State=state)
