"""Switch devices: numbered switches, each on/off or set to a value within its range and steps.

The base checks every call against the device's list of switches before it reaches the hardware:
a wrong switch number, a value outside min..max or off the step grid, or a write to a read-only
switch is refused naming the switch and its range.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from typing import Any

from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import ISwitch, SwitchInfo
from nightcrew.modules.module import Module

__all__ = ["BaseSwitch"]

#: How far (in steps) a value may be from a multiple of the step: float noise, not a wrong value.
_STEP_TOLERANCE = 1e-6


class BaseSwitch(Module, ISwitch):
    """A switch device; a driver fills :attr:`_switches` (e.g. when it connects) and implements
    ``_hw_get_value``/``_hw_set_value`` (on/off go through them unless it has its own)."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        #: The device's switches, index i at position i.
        self._switches: list[SwitchInfo] = []

    @property
    def switch_device(self) -> str:
        """The device's name in error messages."""
        return self.name

    # --- hooks ---------------------------------------------------------------------------------

    @abstractmethod
    async def _hw_get_value(self, switch: int) -> float:
        """Value of switch ``switch``."""

    @abstractmethod
    async def _hw_set_value(self, switch: int, value: float) -> None:
        """Set switch ``switch`` to ``value`` (checked against its range and step)."""

    async def _hw_get_state(self, switch: int) -> bool:
        """Whether switch ``switch`` is on: its value above its minimum."""
        return await self._hw_get_value(switch) > self._switches[switch].min_value

    async def _hw_set_state(self, switch: int, state: bool) -> None:
        """Turn switch ``switch`` on (its maximum) or off (its minimum)."""
        info = self._switches[switch]
        await self._hw_set_value(switch, info.max_value if state else info.min_value)

    # --- checks --------------------------------------------------------------------------------

    def _info(self, switch: int) -> SwitchInfo:
        if not 0 <= switch < len(self._switches):
            raise InvalidArgumentError(
                f"{self.switch_device} has switches 0..{len(self._switches) - 1}, not {switch}"
                if self._switches
                else f"{self.switch_device} has no switches"
            )
        return self._switches[switch]

    def _writable(self, switch: int) -> SwitchInfo:
        info = self._info(switch)
        if not info.can_write:
            raise NotSupportedError(f"{self.switch_device}: switch {switch} ({info.name!r}) is read-only")
        return info

    # --- ISwitch -------------------------------------------------------------------------------

    async def get_switches(self) -> list[SwitchInfo]:
        return list(self._switches)

    async def get_switch(self, switch: int) -> bool:
        self._info(switch)
        return await self._hw_get_state(switch)

    async def set_switch(self, switch: int, state: bool) -> None:
        self._writable(switch)
        await self._hw_set_state(switch, bool(state))

    async def get_switch_value(self, switch: int) -> float:
        self._info(switch)
        return await self._hw_get_value(switch)

    async def set_switch_value(self, switch: int, value: float) -> None:
        info = self._writable(switch)
        where = f"{self.switch_device}: switch {switch} ({info.name!r})"
        if not (math.isfinite(value) and info.min_value <= value <= info.max_value):
            raise InvalidArgumentError(f"{where}: {value} is outside {info.min_value:g}..{info.max_value:g}")
        if info.step > 0:
            steps = (value - info.min_value) / info.step
            if abs(steps - round(steps)) > _STEP_TOLERANCE:
                raise InvalidArgumentError(
                    f"{where}: {value} is not {info.min_value:g} plus a multiple of the step {info.step:g}"
                )
        await self._hw_set_value(switch, float(value))
