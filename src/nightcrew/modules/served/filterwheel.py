"""The served filter wheel: what Alpaca and INDI clients ask of a nightcrew IFilters, written once.

Clients count a wheel's positions (Alpaca from 0, INDI from 1); nightcrew names its filters. A
position is the index of a filter in the module's ``list_filters()``; a wheel whose current filter
is not in that list (or not known yet) has no position.
"""

from __future__ import annotations

from nightcrew.interfaces import IFilters, MotionStatus

__all__ = ["ServedFilterWheelRole"]


class ServedFilterWheelRole:
    """The IFilters module behind a served filter wheel."""

    def __init__(self, wheel: IFilters) -> None:
        self.wheel = wheel

    async def names(self) -> list[str]:
        return await self.wheel.list_filters()

    async def index(self, names: list[str]) -> int | None:
        """The current filter's index in ``names`` (0-based), None if it is not there."""
        current = await self.wheel.get_filter()
        return names.index(current) if current in names else None

    async def select(self, names: list[str], index: int) -> None:
        """Turn to ``names[index]`` (the adapter has checked the index against its protocol)."""
        await self.wheel.set_filter(names[index])

    async def status(self) -> MotionStatus:
        return await self.wheel.get_motion_status()
