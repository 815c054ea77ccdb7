"""The Moon: position, altitude at a site and illuminated fraction.

The position comes from the low-precision series of the Astronomical Almanac (~0.3°), geocentric:
the topocentric parallax (up to 1°) is ignored. Good for a Moon separation header, sky brightness
and scheduling limits. All angles in degrees, times as Unix seconds (UTC), one or a numpy array.
"""

from __future__ import annotations

from nightcrew.astro._math import DEG, Real, elementary
from nightcrew.astro.coords import (
    angular_separation,
    ecliptic_to_equatorial,
    from_unit_vector,
    precess,
    radec_to_altaz,
)
from nightcrew.astro.sun import sun_radec
from nightcrew.astro.time import julian_centuries

__all__ = ["moon_altitude", "moon_illumination", "moon_radec"]


def moon_radec(unix_time: Real) -> tuple[Real, Real]:
    """Geocentric ICRS (ra, dec) of the Moon to ~0.3°, at one time or an array."""
    xp = elementary(unix_time)
    t = julian_centuries(unix_time)

    def sin_d(x: Real) -> Real:
        return xp.sin(x * DEG)

    lon = (
        218.32
        + 481267.881 * t
        + 6.29 * sin_d(135.0 + 477198.87 * t)
        - 1.27 * sin_d(259.3 - 413335.36 * t)
        + 0.66 * sin_d(235.7 + 890534.22 * t)
        + 0.21 * sin_d(269.9 + 954397.74 * t)
        - 0.19 * sin_d(357.5 + 35999.05 * t)
        - 0.11 * sin_d(186.5 + 966404.03 * t)
    )
    lat = (
        5.13 * sin_d(93.3 + 483202.02 * t)
        + 0.28 * sin_d(228.2 + 960400.89 * t)
        - 0.28 * sin_d(318.3 + 6003.15 * t)
        - 0.17 * sin_d(217.6 - 407332.21 * t)
    )
    of_date = ecliptic_to_equatorial(lon, lat, 23.439 - 0.0130 * t, xp)
    return from_unit_vector(precess(of_date, unix_time, xp, inverse=True), xp)


def moon_altitude(latitude: float, longitude: float, unix_time: Real) -> Real:
    """Altitude of the Moon seen from the site (geocentric position: parallax up to 1° ignored)."""
    alt, _ = radec_to_altaz(*moon_radec(unix_time), latitude, longitude, unix_time)
    return alt


def moon_illumination(unix_time: Real) -> Real:
    """Illuminated fraction of the Moon's disc, 0 (new) .. 1 (full), from its elongation."""
    elongation = angular_separation(*sun_radec(unix_time), *moon_radec(unix_time))
    return (1.0 - elementary(unix_time).cos(elongation * DEG)) / 2.0
