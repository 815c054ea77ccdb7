"""The Moon: position, altitude at a site and illuminated fraction.

The position comes from the low-precision series of the Astronomical Almanac (~0.3°), geocentric:
the topocentric parallax (up to 1°) is ignored. Good for a Moon separation header, sky brightness
and scheduling limits. All angles in degrees, times as Unix seconds (UTC).
"""

from __future__ import annotations

import math

from nightcrew.astro.coords import (
    angular_separation,
    ecliptic_to_equatorial,
    from_unit_vector,
    precession_matrix,
    radec_to_altaz,
)
from nightcrew.astro.sun import sun_radec
from nightcrew.astro.time import julian_centuries

__all__ = ["moon_altitude", "moon_illumination", "moon_radec"]


def _sin_d(x: float) -> float:
    return math.sin(math.radians(x))


def moon_radec(unix_time: float) -> tuple[float, float]:
    """Geocentric ICRS (ra, dec) of the Moon to ~0.3°."""
    t = julian_centuries(unix_time)
    lon = (
        218.32
        + 481267.881 * t
        + 6.29 * _sin_d(135.0 + 477198.87 * t)
        - 1.27 * _sin_d(259.3 - 413335.36 * t)
        + 0.66 * _sin_d(235.7 + 890534.22 * t)
        + 0.21 * _sin_d(269.9 + 954397.74 * t)
        - 0.19 * _sin_d(357.5 + 35999.05 * t)
        - 0.11 * _sin_d(186.5 + 966404.03 * t)
    )
    lat = (
        5.13 * _sin_d(93.3 + 483202.02 * t)
        + 0.28 * _sin_d(228.2 + 960400.89 * t)
        - 0.28 * _sin_d(318.3 + 6003.15 * t)
        - 0.17 * _sin_d(217.6 - 407332.21 * t)
    )
    of_date = ecliptic_to_equatorial(lon, lat, 23.439 - 0.0130 * t)
    ra, dec = from_unit_vector(precession_matrix(unix_time).T @ of_date)
    return float(ra), float(dec)


def moon_altitude(latitude: float, longitude: float, unix_time: float) -> float:
    """Altitude of the Moon seen from the site (geocentric position: parallax up to 1° ignored)."""
    alt, _ = radec_to_altaz(*moon_radec(unix_time), latitude, longitude, unix_time)
    return alt


def moon_illumination(unix_time: float) -> float:
    """Illuminated fraction of the Moon's disc, 0 (new) .. 1 (full), from its elongation."""
    elongation = angular_separation(*sun_radec(unix_time), *moon_radec(unix_time))
    return (1.0 - math.cos(math.radians(elongation))) / 2.0
