"""Filter wheels."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.motion import IMotion
from nightcrew.timeout import timeout

__all__ = ["IFilters"]


class IFilters(IMotion):
    """A filter wheel (or slide) with named filters."""

    @abstractmethod
    async def list_filters(self) -> list[str]:
        """Names of the available filters."""

    @timeout(120)
    @abstractmethod
    async def set_filter(self, filter_name: str) -> None:
        """Move filter ``filter_name`` into the beam."""

    @abstractmethod
    async def get_filter(self) -> str:
        """Name of the filter in the beam."""
