"""Switches: power outlets, relays, dew heaters, lights, each on/off or set to a value."""

from __future__ import annotations

from abc import abstractmethod
from dataclasses import dataclass

from nightcrew.interfaces.base import Interface
from nightcrew.interfaces.quantities import SwitchIndex

__all__ = ["ISwitch", "SwitchInfo"]


@dataclass(frozen=True)
class SwitchInfo:
    """One switch of a switch device.

    An on/off switch has ``min_value`` 0, ``max_value`` 1 and ``step`` 1; an analog one (a dew
    heater's power, a dimmer) any range, set in multiples of ``step`` from ``min_value``.
    """

    #: Number of the switch on its device, 0..count-1 (Alpaca's Id); the ``switch`` argument of the calls.
    index: int
    name: str
    description: str
    #: Whether the switch can be set; False for read-only sensors (e.g. a voltage).
    can_write: bool
    min_value: float
    max_value: float
    step: float


class ISwitch(Interface):
    """A device with numbered switches, each with a value between its min and max (on/off = 1/0).

    ``switch`` in every method is a switch's index: its position in :meth:`get_switches`, from 0.
    """

    @abstractmethod
    async def get_switches(self) -> list[SwitchInfo]:
        """Every switch of the device, in index order."""

    @abstractmethod
    async def get_switch(self, switch: SwitchIndex) -> bool:
        """Whether switch ``switch`` is on (its value is above its minimum)."""

    @abstractmethod
    async def set_switch(self, switch: SwitchIndex, state: bool) -> None:
        """Turn switch ``switch`` on (its maximum) or off (its minimum)."""

    @abstractmethod
    async def get_switch_value(self, switch: SwitchIndex) -> float:
        """Value of switch ``switch``, between its min_value and max_value."""

    @abstractmethod
    async def set_switch_value(self, switch: SwitchIndex, value: float) -> None:
        """Set switch ``switch`` to ``value`` (within min..max, a multiple of step from min)."""
