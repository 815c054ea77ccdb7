"""The served filter wheel's INDI adapter: a nightcrew filter wheel (IFilters) as an INDI filter wheel.

==========================  ======================================================================
property                    nightcrew
==========================  ======================================================================
FILTER_SLOT                 filter wheel get_filter()/set_filter(), slots 1..N in list_filters() order
FILTER_NAME (ro)            list_filters()
==========================  ======================================================================

The work on the module is the served filter wheel role's (:mod:`nightcrew.modules.served.filterwheel`),
which the Alpaca FilterWheel shares.
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.indi.server_vectors import (
    NumberMember,
    Permission,
    Property,
    PropertyState,
    TextMember,
)
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import IFilters, MotionStatus
from nightcrew.modules.served.device_indi import MAIN_GROUP, ServedDevice, Values
from nightcrew.modules.served.filterwheel import ServedFilterWheelRole

__all__ = ["ServedFilterWheel"]


class ServedFilterWheel(ServedDevice[IFilters]):
    """An IFilters module as an INDI filter wheel."""

    interface = IFilters
    driver_interface = 16

    @property
    def role(self) -> ServedFilterWheelRole:
        return ServedFilterWheelRole(self.device)

    async def _build(self) -> list[Property[Any]]:
        self.filters = await self.role.names()
        count = float(len(self.filters))
        self.slot = Property(
            self.name,
            "FILTER_SLOT",
            "Filter Slot",
            MAIN_GROUP,
            [NumberMember("FILTER_SLOT_VALUE", "Filter", 1.0, 1.0, count, 1.0, "%3.0f")],
            timeout=120.0,
        )
        self.names = Property(
            self.name,
            "FILTER_NAME",
            "Filter",
            MAIN_GROUP,
            [
                TextMember(f"FILTER_SLOT_NAME_{i}", f"Filter #{i}", name)
                for i, name in enumerate(self.filters, 1)
            ],
            perm=Permission.READ_ONLY,
            state=PropertyState.OK,
        )
        return [self.slot, self.names]

    async def _update(self) -> None:
        role = self.role
        status = await role.status()
        index = await role.index(self.filters)
        if index is not None:
            self.slot.by_name["FILTER_SLOT_VALUE"].value = float(index + 1)
        self._follow(self.slot, busy=status is MotionStatus.MOVING, failed=status is MotionStatus.ERROR)

    async def _request(self, vector: Property[Any], values: Values) -> None:
        if vector is not self.slot:
            raise InvalidArgumentError(f"{vector.where} cannot be set")
        slot = float(values["FILTER_SLOT_VALUE"])
        if slot != int(slot):
            raise InvalidArgumentError(
                f"{vector.where}: a filter slot is a whole number 1..{len(self.filters)}, got {slot:g}"
            )
        self._start(self.slot, self.role.select(self.filters, int(slot) - 1))
