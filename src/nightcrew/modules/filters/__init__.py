"""Filter wheels: the base class for their drivers."""

from nightcrew.modules.filters.base import BaseFilterWheel

__all__ = ["BaseFilterWheel"]
