"""Sun and Moon for the simulated sky, as fast pure functions (no astropy at run time).

The Sun comes from the low-precision formulae of the Astronomical Almanac (about 0.01° over
1950-2050, in the mean equator of date; we skip precession to J2000, ~0.4° in 2026, far below what a
sky brightness needs). The Moon comes from :func:`~nightcrew.modules.telescope.coords.moon_radec`.
All angles in degrees, times as Unix seconds (UTC).
"""

from __future__ import annotations

import math
from datetime import UTC, date, datetime

from nightcrew.modules.telescope.coords import (
    angular_separation,
    julian_date,
    moon_radec,
    radec_to_altaz,
)

__all__ = ["astronomical_dusk", "moon_altitude", "moon_illumination", "sun_altitude", "sun_radec"]

_J2000 = 2451545.0
#: The Sun's altitude at the end of astronomical twilight.
ASTRONOMICAL_TWILIGHT = -18.0


def sun_radec(unix_time: float) -> tuple[float, float]:
    """Apparent (ra, dec) of the Sun to ~0.01° (mean equator of date)."""
    n = julian_date(unix_time) - _J2000
    mean_longitude = 280.460 + 0.9856474 * n
    mean_anomaly = math.radians(357.528 + 0.9856003 * n)
    ecliptic_longitude = math.radians(
        mean_longitude + 1.915 * math.sin(mean_anomaly) + 0.020 * math.sin(2.0 * mean_anomaly)
    )
    obliquity = math.radians(23.439 - 0.0000004 * n)
    ra = math.degrees(
        math.atan2(math.cos(obliquity) * math.sin(ecliptic_longitude), math.cos(ecliptic_longitude))
    )
    dec = math.degrees(math.asin(math.sin(obliquity) * math.sin(ecliptic_longitude)))
    return ra % 360.0, dec


def sun_altitude(latitude: float, longitude: float, unix_time: float) -> float:
    """Altitude of the Sun's centre seen from the site (no refraction)."""
    alt, _ = radec_to_altaz(*sun_radec(unix_time), latitude, longitude, unix_time)
    return alt


def moon_altitude(latitude: float, longitude: float, unix_time: float) -> float:
    """Altitude of the Moon seen from the site (geocentric position: parallax up to 1° ignored)."""
    alt, _ = radec_to_altaz(*moon_radec(unix_time), latitude, longitude, unix_time)
    return alt


def moon_illumination(unix_time: float) -> float:
    """Illuminated fraction of the Moon's disc, 0 (new) .. 1 (full), from its elongation."""
    elongation = angular_separation(*sun_radec(unix_time), *moon_radec(unix_time))
    return (1.0 - math.cos(math.radians(elongation))) / 2.0


def astronomical_dusk(night: date, latitude: float, longitude: float) -> float:
    """Unix time when the Sun sinks below -18° in the evening of ``night`` (local solar time).

    Raises:
        ValueError: the Sun does not reach -18° that night (polar summer) or never rises above it.
    """
    # Search from local noon over the next 18 hours, in 10-minute steps, then bisect.
    noon = datetime(night.year, night.month, night.day, 12, tzinfo=UTC).timestamp() - longitude / 15.0 * 3600
    step = 600.0

    def above(t: float) -> bool:
        return sun_altitude(latitude, longitude, t) > ASTRONOMICAL_TWILIGHT

    if not above(noon):
        raise ValueError(f"the Sun stays below {ASTRONOMICAL_TWILIGHT}° on {night} at latitude {latitude}")
    t = noon
    while above(t + step):
        t += step
        if t > noon + 18 * 3600:
            raise ValueError(f"no astronomical night on {night} at latitude {latitude}")
    low, high = t, t + step
    while high - low > 1.0:
        middle = (low + high) / 2.0
        low, high = (middle, high) if above(middle) else (low, middle)
    return high
