"""FITS header providers: modules asked by a camera for header cards before and after an exposure."""

from __future__ import annotations

from abc import abstractmethod
from typing import TypeAlias

from nightcrew.interfaces.base import Interface

__all__ = ["FitsCard", "FitsValue", "IFitsHeaderAfter", "IFitsHeaderBefore"]

#: What a FITS card can hold (dates are written as ISO strings). int comes before float on purpose:
#: the codec tries union members in order, and float would turn a whole number 3 into 3.0.
FitsValue: TypeAlias = bool | int | float | str | None
#: A card's (value, comment).
FitsCard: TypeAlias = tuple[FitsValue, str]


class IFitsHeaderBefore(Interface):
    """Provides header cards at the start of an exposure (e.g. telescope position).

    ``namespaces`` (here and in IFitsHeaderAfter) are the groups of cards a caller wants, pyobs'
    convention (a camera may ask by name); None for all. nightcrew's cameras ask with None, and
    nightcrew's providers give all their cards whatever it says.
    """

    @abstractmethod
    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        """Keyword → (value, comment); ``namespaces``: card groups (None: all; see IFitsHeaderBefore)."""


class IFitsHeaderAfter(Interface):
    """Provides header cards at the end of an exposure (e.g. averages over the exposure)."""

    @abstractmethod
    async def get_fits_header_after(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        """Keyword → (value, comment); ``namespaces``: card groups (None: all; see IFitsHeaderBefore)."""
