"""A simulated switch device: outlets, a dimmer or a dew heater, as many as configured."""

from __future__ import annotations

import math
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.interfaces import SwitchInfo
from nightcrew.modules.switch import BaseSwitch

__all__ = ["SimSwitch"]

_KEYS = ("name", "description", "can_write", "min_value", "max_value", "step", "value")


def _switch(index: int, options: dict[str, Any]) -> tuple[SwitchInfo, float]:
    """One configured switch and its starting value; ConfigError naming the key if wrong."""
    key = f"switches[{index}]"
    unknown = sorted(set(options) - set(_KEYS))
    if unknown:
        raise ConfigError(f"unknown keys {unknown}; known: {', '.join(_KEYS)}", key=key)
    if not options.get("name"):
        raise ConfigError("every switch needs a name", key=f"{key}.name")
    try:
        info = SwitchInfo(
            index=index,
            name=str(options["name"]),
            description=str(options.get("description", "")),
            can_write=bool(options.get("can_write", True)),
            min_value=float(options.get("min_value", 0.0)),
            max_value=float(options.get("max_value", 1.0)),
            step=float(options.get("step", 1.0)),
        )
        value = float(options.get("value", info.min_value))
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"min_value, max_value, step and value must be numbers ({exc})", key=key) from None
    numbers = (info.min_value, info.max_value, info.step, value)
    if not (all(map(math.isfinite, numbers)) and info.min_value < info.max_value):
        raise ConfigError(f"need min_value < max_value, got {info.min_value}..{info.max_value}", key=key)
    if not 0 <= info.step <= info.max_value - info.min_value:
        raise ConfigError(f"step must be within 0..max_value - min_value, got {info.step}", key=f"{key}.step")
    if not info.min_value <= value <= info.max_value:
        raise ConfigError(f"must be within {info.min_value:g}..{info.max_value:g}", key=f"{key}.value")
    return info, value


class SimSwitch(BaseSwitch):
    """Switches in the simulated observatory.

    Args:
        switches: One mapping per switch: ``name`` and optionally ``description``, ``can_write``
            (true), ``min_value`` (0), ``max_value`` (1), ``step`` (1) and the starting ``value``
            (the minimum). The defaults make an on/off switch.
        **kwargs: Module options.
    """

    def __init__(self, *, switches: list[dict[str, Any]], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        built = [_switch(index, options) for index, options in enumerate(switches)]
        self._switches = [info for info, _ in built]
        #: Current value of each switch.
        self.values = [value for _, value in built]

    async def _hw_get_value(self, switch: int) -> float:
        return self.values[switch]

    async def _hw_set_value(self, switch: int, value: float) -> None:
        self.values[switch] = value
