"""Where a telescope (or dome) points, and offsets from that position. All angles in degrees."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.base import Interface
from nightcrew.interfaces.enums import PierSide
from nightcrew.interfaces.motion import IMotion
from nightcrew.interfaces.quantities import Altitude, Azimuth, Declination, Degrees, RightAscension
from nightcrew.timeout import timeout

__all__ = [
    "IOffsetsAltAz",
    "IOffsetsRaDec",
    "IPierSide",
    "IPointingAltAz",
    "IPointingRaDec",
    "ISyncRaDec",
    "ITelescope",
]


class IPointingRaDec(Interface):
    """Pointing at equatorial (ICRS) coordinates, and tracking them."""

    @timeout(300)
    @abstractmethod
    async def move_radec(self, ra: RightAscension, dec: Declination) -> None:
        """Slew to right ascension ``ra`` and declination ``dec`` (degrees) and track."""

    @abstractmethod
    async def get_radec(self) -> tuple[float, float]:
        """Current (ra, dec) in degrees."""


class IPointingAltAz(Interface):
    """Pointing at horizontal coordinates, without tracking."""

    @timeout(300)
    @abstractmethod
    async def move_altaz(self, alt: Altitude, az: Azimuth) -> None:
        """Move to altitude ``alt`` and azimuth ``az`` (degrees, azimuth east of north)."""

    @abstractmethod
    async def get_altaz(self) -> tuple[float, float]:
        """Current (alt, az) in degrees."""


class IOffsetsRaDec(Interface):
    """Offsets along the RA and Dec axes, added to the target position (guiding, acquisition)."""

    @timeout(60)
    @abstractmethod
    async def set_offsets_radec(self, dra: Degrees, ddec: Degrees) -> None:
        """Set the offsets along the RA axis (not scaled by cos dec) and Dec axis, in degrees."""

    @abstractmethod
    async def get_offsets_radec(self) -> tuple[float, float]:
        """Current (dra, ddec) offsets in degrees."""


class IOffsetsAltAz(Interface):
    """Offsets along the altitude and azimuth axes, added to the target position."""

    @timeout(60)
    @abstractmethod
    async def set_offsets_altaz(self, dalt: Degrees, daz: Degrees) -> None:
        """Set the offsets along the altitude and azimuth axes, in degrees."""

    @abstractmethod
    async def get_offsets_altaz(self) -> tuple[float, float]:
        """Current (dalt, daz) offsets in degrees."""


class ITelescope(IMotion, IPointingRaDec, IPointingAltAz):
    """A telescope mount: a moving device that points in both coordinate systems."""


class ISyncRaDec(Interface):
    """Telling a mount where it really points (e.g. after a plate solve), so it corrects itself."""

    @abstractmethod
    async def sync_radec(self, ra: RightAscension, dec: Declination) -> None:
        """The mount points at ICRS (``ra``, ``dec``) degrees now; it must be tracking."""


class IPierSide(Interface):
    """The pointing state of a German-equatorial mount (see :class:`PierSide`)."""

    @abstractmethod
    async def get_pier_side(self) -> PierSide:
        """The side of the pier the mount is on now (UNKNOWN if it cannot tell)."""

    @abstractmethod
    async def get_destination_pier_side(self, ra: RightAscension, dec: Declination) -> PierSide:
        """The side a slew to ICRS (``ra``, ``dec``) degrees would end on now (UNKNOWN if it cannot tell)."""
