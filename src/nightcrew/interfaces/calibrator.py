"""Flat-field panels with an optional telescope cover: what a dome-flat script drives."""

from __future__ import annotations

from abc import abstractmethod
from enum import StrEnum

from nightcrew.interfaces.base import Interface
from nightcrew.timeout import timeout

__all__ = ["CalibratorState", "CoverState", "ICoverCalibrator"]


class CoverState(StrEnum):
    """Where a telescope cover is."""

    NOT_PRESENT = "not_present"  # the device has no cover
    CLOSED = "closed"
    MOVING = "moving"
    OPEN = "open"
    UNKNOWN = "unknown"  # e.g. stopped halfway
    ERROR = "error"


class CalibratorState(StrEnum):
    """What a flat-field light source is doing."""

    NOT_PRESENT = "not_present"  # the device has no light
    OFF = "off"
    NOT_READY = "not_ready"  # on, but still warming up or settling
    READY = "ready"  # on and stable: take flats now
    UNKNOWN = "unknown"
    ERROR = "error"


class ICoverCalibrator(Interface):
    """A cover in front of the telescope and/or a light for flat fields (a flip-flat, a dome panel).

    A part the device does not have reports NOT_PRESENT and refuses to be driven.
    """

    @timeout(120)
    @abstractmethod
    async def open_cover(self) -> None:
        """Open the cover; return when it is open."""

    @timeout(120)
    @abstractmethod
    async def close_cover(self) -> None:
        """Close the cover; return when it is closed."""

    @abstractmethod
    async def halt_cover(self) -> None:
        """Stop a moving cover where it is."""

    @abstractmethod
    async def get_cover_state(self) -> CoverState:
        """Where the cover is."""

    @timeout(120)
    @abstractmethod
    async def calibrator_on(self, brightness: int) -> None:
        """Switch the light on at ``brightness`` (0..max brightness); return when it is stable."""

    @timeout(60)
    @abstractmethod
    async def calibrator_off(self) -> None:
        """Switch the light off; return when it is off."""

    @abstractmethod
    async def get_calibrator_state(self) -> CalibratorState:
        """What the light is doing."""

    @abstractmethod
    async def get_brightness(self) -> int:
        """Current brightness of the light, 0 when off."""

    @abstractmethod
    async def get_max_brightness(self) -> int:
        """Highest brightness the light can be set to."""
