"""Turning a measured pointing error into telescope offsets.

A pointing error is an on-sky ``(east, north)`` offset in arcsec: where the telescope points minus
where it should (:class:`~nightcrew.images.processors.offsets.Offsets` gives it as ``d_ra_arcsec``,
``d_dec_arcsec`` when the image has a WCS; :func:`pixel_error_to_sky` makes it from pixel offsets
otherwise). :class:`ApplyRaDecOffsets` and :class:`ApplyAltAzOffsets` *accumulate*: the new
offsets are the telescope's current ones minus the error, expressed along the mount's axes.
"""

from __future__ import annotations

import abc
import math
from dataclasses import dataclass
from typing import Any

from nightcrew.astro import altaz_to_radec, radec_to_altaz
from nightcrew.errors import InvalidArgumentError
from nightcrew.images import Image
from nightcrew.images.processors.offsets import Offsets
from nightcrew.interfaces import IOffsetsAltAz, IOffsetsRaDec, IPointingAltAz, IPointingRaDec
from nightcrew.object import Object

__all__ = [
    "ApplyAltAzOffsets",
    "ApplyOffsets",
    "ApplyRaDecOffsets",
    "SkyError",
    "pixel_error_to_sky",
    "sky_error",
]


@dataclass(frozen=True)
class SkyError:
    """A pointing error on the sky in arcsec (east = RA times cos Dec)."""

    east: float
    north: float

    @property
    def distance(self) -> float:
        return math.hypot(self.east, self.north)

    def __add__(self, other: SkyError) -> SkyError:
        return SkyError(self.east + other.east, self.north + other.north)

    def scaled(self, factor: float) -> SkyError:
        return SkyError(self.east * factor, self.north * factor)

    def limited(self, limit: float) -> SkyError:
        """The same direction, at most ``limit`` arcsec long."""
        return self.scaled(limit / self.distance) if self.distance > limit else self


def pixel_error_to_sky(
    dx: float, dy: float, pixel_scale: float, *, position_angle: float = 0.0, flip: bool = False
) -> SkyError:
    """The pointing error when the stars sit ``(dx, dy)`` pixels from where they should.

    Detector orientation: with ``position_angle`` 0 north is +y and east is -x (``flip``: +x);
    a positive angle turns +y from north towards east (the convention of :mod:`nightcrew.sim`).
    The frame's centre shows the sky that belonged at ``centre - (dx, dy)``.
    """
    r = math.radians(position_angle)
    du, dv = -dx * (-1.0 if flip else 1.0), -dy
    east = pixel_scale * (-math.cos(r) * du + math.sin(r) * dv)
    north = pixel_scale * (math.sin(r) * du + math.cos(r) * dv)
    return SkyError(east, north)


def sky_error(offsets: Offsets, image: Image, *, position_angle: float = 0.0, flip: bool = False) -> SkyError:
    """The pointing error an offsets processor found: from the WCS if it had one, else the pixels.

    Raises:
        InvalidArgumentError: No WCS and no pixel scale in the header.
    """
    if offsets.d_ra_arcsec is not None and offsets.d_dec_arcsec is not None:
        return SkyError(offsets.d_ra_arcsec, offsets.d_dec_arcsec)
    scale = image.pixel_scale
    if scale is None:
        raise InvalidArgumentError("the image has neither a WCS nor a pixel scale: cannot convert offsets")
    return pixel_error_to_sky(offsets.dx, offsets.dy, scale, position_angle=position_angle, flip=flip)


class ApplyOffsets(Object, abc.ABC):
    """Moves a telescope by offsets that cancel a pointing error.

    Args:
        telescope: The telescope module (name) or object.
        **kwargs: Object context.
    """

    def __init__(self, telescope: str = "telescope", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.telescope = telescope

    @abc.abstractmethod
    async def current(self) -> SkyError:
        """The telescope's current offsets as an on-sky shift (arcsec)."""

    @abc.abstractmethod
    async def apply(self, error: SkyError) -> None:
        """Add the offsets that cancel ``error`` to the telescope's current offsets."""


class ApplyRaDecOffsets(ApplyOffsets):
    """Corrects with IOffsetsRaDec: RA offsets are along the RA axis, so east is divided by cos Dec."""

    async def _dec(self) -> float:
        return (await (await self.proxy(self.telescope, IPointingRaDec)).get_radec())[1]

    async def current(self) -> SkyError:
        dra, ddec = await (await self.proxy(self.telescope, IOffsetsRaDec)).get_offsets_radec()
        return SkyError(dra * 3600.0 * math.cos(math.radians(await self._dec())), ddec * 3600.0)

    async def apply(self, error: SkyError) -> None:
        telescope = await self.proxy(self.telescope, IOffsetsRaDec)
        dra, ddec = await telescope.get_offsets_radec()
        cos_dec = max(math.cos(math.radians(await self._dec())), 1e-6)
        await telescope.set_offsets_radec(dra - error.east / cos_dec / 3600.0, ddec - error.north / 3600.0)


class ApplyAltAzOffsets(ApplyOffsets):
    """Corrects with IOffsetsAltAz; the sky error is turned into alt/az through the site's geometry.

    Args:
        telescope: Module offering IOffsetsAltAz and IPointingAltAz.
        **kwargs: Object context (needs the site).
    """

    async def _altaz(self) -> tuple[float, float]:
        return await (await self.proxy(self.telescope, IPointingAltAz)).get_altaz()

    async def current(self) -> SkyError:
        dalt, daz = await (await self.proxy(self.telescope, IOffsetsAltAz)).get_offsets_altaz()
        alt, az = await self._altaz()
        ra, dec = altaz_to_radec(alt, az, *self._latlon(), self.clock.time())
        ra1, dec1 = altaz_to_radec(alt + dalt, az + daz, *self._latlon(), self.clock.time())
        d_ra = (ra1 - ra + 180.0) % 360.0 - 180.0
        return SkyError(d_ra * 3600.0 * math.cos(math.radians(dec)), (dec1 - dec) * 3600.0)

    async def apply(self, error: SkyError) -> None:
        telescope = await self.proxy(self.telescope, IOffsetsAltAz)
        dalt, daz = await telescope.get_offsets_altaz()
        alt, az = await self._altaz()
        e_alt, e_az = sky_to_altaz_error(error, alt, az, *self._latlon(), self.clock.time())
        await telescope.set_offsets_altaz(dalt - e_alt / 3600.0, daz - e_az / 3600.0)

    def _latlon(self) -> tuple[float, float]:
        if self.site is None:
            raise InvalidArgumentError("ApplyAltAzOffsets needs the observatory site")
        return self.site.latitude, self.site.longitude


def sky_to_altaz_error(
    error: SkyError, alt: float, az: float, latitude: float, longitude: float, unix_time: float
) -> tuple[float, float]:
    """``error`` (east, north arcsec) at (alt, az) as (altitude, azimuth) arcsec along the axes.

    The parallactic rotation is taken numerically from the coordinate transform (1' steps), so it
    holds wherever the transform does; azimuth is divided by cos alt (axis, not sky, angle).
    """
    ra, dec = altaz_to_radec(alt, az, latitude, longitude, unix_time)
    step = 1.0 / 60.0
    cos_dec = max(math.cos(math.radians(dec)), 1e-6)
    a0, z0 = radec_to_altaz(ra, dec, latitude, longitude, unix_time)
    ae, ze = radec_to_altaz(ra + step / cos_dec, dec, latitude, longitude, unix_time)
    an, zn = radec_to_altaz(ra, dec + step, latitude, longitude, unix_time)

    def d_az(z: float) -> float:
        return (z - z0 + 180.0) % 360.0 - 180.0

    e, n = error.east / 3600.0 / step, error.north / 3600.0 / step
    return ((ae - a0) * e + (an - a0) * n) * 3600.0, (d_az(ze) * e + d_az(zn) * n) * 3600.0
