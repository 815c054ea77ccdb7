"""The Moon: position (geocentric or seen from a site), altitude and illuminated fraction.

The geocentric position is ERFA's ``moon98`` (Meeus's simplified ELP-2000/82: about 10" over
1900-2100), in J2000 axes; seen from a site the Moon shifts by up to ~1° (its horizontal parallax,
:mod:`~nightcrew.astro.parallax`), which every altitude and separation limit must count. All angles
in degrees, times as Unix seconds (UTC), one or a numpy array.
"""

from __future__ import annotations

from typing import cast

import erfa  # type: ignore[import-untyped]
import numpy as np

from nightcrew.astro._math import DEG, Real, elementary
from nightcrew.astro.coords import angular_separation, from_unit_vector, radec_to_altaz
from nightcrew.astro.parallax import topocentric_radec
from nightcrew.astro.sun import sun_radec
from nightcrew.site import Site

__all__ = ["moon_altitude", "moon_geocentric", "moon_illumination", "moon_radec"]

_UNIX_EPOCH_JD = 2440587.5
#: TT - UTC since 2017 (32.184 s + 37 leap seconds); a second off moves the Moon 0.5".
_TT_MINUS_UTC_S = 69.184


def moon_geocentric(unix_time: Real) -> tuple[Real, Real, Real]:
    """Geocentric J2000 (ra, dec, distance in AU) of the Moon, at one time or an array."""
    pv = erfa.moon98(_UNIX_EPOCH_JD, (np.asarray(unix_time) + _TT_MINUS_UTC_S) / 86400.0)
    x, y, z = np.moveaxis(np.asarray(erfa.pv2p(pv), dtype=np.float64), -1, 0)
    distance = np.sqrt(x * x + y * y + z * z)
    ra, dec = from_unit_vector((x / distance, y / distance, z / distance), elementary(x))
    if not isinstance(unix_time, np.ndarray):  # a float in, floats out (as every astro function)
        return float(ra), float(dec), float(distance)
    return cast(Real, ra), cast(Real, dec), cast(Real, distance)


def moon_radec(unix_time: Real, site: Site | None = None) -> tuple[Real, Real]:
    """J2000 (ra, dec) of the Moon seen from ``site`` (None: from the Earth's centre)."""
    ra, dec, distance = moon_geocentric(unix_time)
    if site is None:
        return ra, dec
    return topocentric_radec(ra, dec, distance, site, unix_time)


def moon_altitude(latitude: float, longitude: float, unix_time: Real, elevation: float = 0.0) -> Real:
    """Altitude of the Moon seen from the site (topocentric, no refraction)."""
    site = Site(latitude, longitude, elevation)
    alt, _ = radec_to_altaz(*moon_radec(unix_time, site), latitude, longitude, unix_time)
    return alt


def moon_illumination(unix_time: Real) -> Real:
    """Illuminated fraction of the Moon's disc, 0 (new) .. 1 (full), from its elongation."""
    elongation = angular_separation(*sun_radec(unix_time), *moon_radec(unix_time))
    return (1.0 - elementary(unix_time).cos(elongation * DEG)) / 2.0
