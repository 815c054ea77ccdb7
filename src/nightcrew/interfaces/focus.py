"""Focusers, focus models and automatic focusing. Focus positions are in mm."""

from __future__ import annotations

from abc import abstractmethod
from typing import Any

from nightcrew.interfaces.base import Interface
from nightcrew.interfaces.control import IAbortable
from nightcrew.interfaces.motion import IMotion
from nightcrew.interfaces.quantities import ExposureTime, FocusCount, FocusStep
from nightcrew.timeout import timeout

__all__ = ["IAutoFocus", "IFocusModel", "IFocusRange", "IFocuser"]


class IFocuser(IMotion):
    """A focuser: a base position plus an offset (e.g. from a focus model or filter)."""

    @timeout(300)
    @abstractmethod
    async def set_focus(self, focus: float) -> None:
        """Move to base focus position ``focus`` in mm."""

    @abstractmethod
    async def get_focus(self) -> float:
        """Base focus position in mm."""

    @timeout(300)
    @abstractmethod
    async def set_focus_offset(self, offset: float) -> None:
        """Set the offset in mm added to the base position."""

    @abstractmethod
    async def get_focus_offset(self) -> float:
        """Offset in mm added to the base position."""


class IFocusRange(Interface):
    """The positions a focuser can reach (a focus series keeps within them)."""

    @abstractmethod
    async def get_focus_range(self) -> tuple[float, float]:
        """Lowest and highest reachable position (base + offset) in mm."""


class IFocusModel(Interface):
    """A model predicting the best focus from temperatures, filter, etc."""

    @abstractmethod
    async def get_optimal_focus(self) -> float:
        """Best focus in mm for the current conditions."""

    @timeout(300)
    @abstractmethod
    async def set_optimal_focus(self) -> None:
        """Move the focuser to the best focus for the current conditions."""


class IAutoFocus(IAbortable):
    """Finding the best focus by a series of exposures."""

    @timeout(1800)
    @abstractmethod
    async def auto_focus(
        self, count: FocusCount, step: FocusStep, exposure_time: ExposureTime
    ) -> tuple[float, float]:
        """Take ``count`` images ``step`` mm apart, ``exposure_time`` s each; return (focus, error) in mm."""

    @abstractmethod
    async def auto_focus_status(self) -> dict[str, Any]:
        """Progress of a running focus series (free-form: e.g. step, count, last measurement)."""
