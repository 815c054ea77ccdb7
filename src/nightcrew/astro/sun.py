"""The Sun seen from a site: position, altitude and the times it crosses an altitude.

The position comes from the low-precision formulae of the Astronomical Almanac (about 0.01° over
1950-2050, in the mean equator of date), precessed back to J2000 like every other position here,
so that :func:`~nightcrew.astro.coords.radec_to_altaz` (which precesses J2000 to the date) and
separations from J2000 positions hold. All angles in degrees, times as Unix seconds (UTC), one or
a numpy array of them.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from datetime import UTC, date, datetime

import numpy as np

from nightcrew.astro._math import DEG, Real, elementary
from nightcrew.astro.coords import ecliptic_to_equatorial, from_unit_vector, precess, radec_to_altaz
from nightcrew.astro.parallax import topocentric_radec
from nightcrew.astro.time import J2000, julian_date
from nightcrew.site import Site

__all__ = [
    "ASTRONOMICAL_TWILIGHT",
    "astronomical_dusk",
    "local_noon",
    "sun_altaz",
    "sun_altitude",
    "sun_altitude_at",
    "sun_crossing",
    "sun_radec",
]

#: The Sun's altitude at the end of astronomical twilight.
ASTRONOMICAL_TWILIGHT = -18.0


def sun_radec(unix_time: Real, site: Site | None = None) -> tuple[Real, Real]:
    """J2000 (ra, dec) of the Sun to ~0.01°, seen from ``site`` (None: from the Earth's centre; the
    difference, the Sun's parallax, is 8.8" at most), at one time or an array."""
    xp = elementary(unix_time)
    n = julian_date(unix_time) - J2000
    mean_longitude = 280.460 + 0.9856474 * n
    mean_anomaly = (357.528 + 0.9856003 * n) * DEG
    ecliptic_longitude = mean_longitude + 1.915 * xp.sin(mean_anomaly) + 0.020 * xp.sin(2.0 * mean_anomaly)
    of_date = ecliptic_to_equatorial(ecliptic_longitude, 0.0, 23.439 - 0.0000004 * n, xp)
    ra, dec = from_unit_vector(precess(of_date, unix_time, xp, inverse=True), xp)
    if site is None:
        return ra, dec
    distance_au = 1.00014 - 0.01671 * xp.cos(mean_anomaly) - 0.00014 * xp.cos(2.0 * mean_anomaly)
    return topocentric_radec(ra, dec, distance_au, site, unix_time)


def sun_altitude(latitude: float, longitude: float, unix_time: Real, elevation: float = 0.0) -> Real:
    """Altitude of the Sun's centre seen from the site (topocentric, no refraction), at one time or
    an array."""
    site = Site(latitude, longitude, elevation)
    alt, _ = radec_to_altaz(*sun_radec(unix_time, site), latitude, longitude, unix_time)
    return alt


def sun_altaz(site: Site, unix_time: Real) -> tuple[Real, Real]:
    """(altitude, azimuth) of the Sun in degrees at ``unix_time`` seen from ``site``, azimuth east of
    north."""
    return radec_to_altaz(*sun_radec(unix_time, site), site.latitude, site.longitude, unix_time)


def sun_altitude_at(site: Site) -> Callable[[float], float]:
    """The Sun's altitude at ``site`` as a function of Unix time (what the twilight planner takes)."""
    return lambda unix_time: sun_altitude(site.latitude, site.longitude, unix_time, site.elevation)


def local_noon(night: date, longitude: float) -> float:
    """Unix time of mean local solar noon on ``night`` at east ``longitude`` (no equation of time)."""
    return datetime(night.year, night.month, night.day, 12, tzinfo=UTC).timestamp() - longitude / 15.0 * 3600


def sun_crossing(
    site: Site,
    after: float,
    altitude: float,
    *,
    rising: bool,
    within: float = 86400.0,
    step: float = 600.0,
) -> float:
    """Unix time of the first crossing of ``altitude`` by the Sun after ``after`` (to a second).

    The Sun is sampled every ``step`` seconds (in one array call) and the crossing bisected; the
    result is the first second found on the far side (above when ``rising``, at or below when
    setting).

    Raises:
        ValueError: no such crossing ``within`` seconds (polar day or night).
    """
    # The samples in one array call: the first on the near side (the search starts by getting past
    # a crossing it is beyond already), then the first beyond it, each no further than ``within``
    # from ``after`` (the far one may be a step more).
    times = after + step * np.arange(math.floor(within / step) + 3, dtype=np.float64)
    far = (sun_altitude(site.latitude, site.longitude, times) > altitude) == rising
    in_window = times <= after + within
    near = np.flatnonzero(~far & in_window)
    crossed = np.flatnonzero(far[near[0] + 1 :] & in_window[near[0] : -1]) if near.size else near
    if not crossed.size:
        raise ValueError(f"the Sun does not cross {altitude}° within {within / 3600:g} h")
    low, high = float(times[near[0] + crossed[0]]), float(times[near[0] + crossed[0] + 1])
    while high - low > 1.0:
        middle = (low + high) / 2.0
        beyond = (sun_altitude(site.latitude, site.longitude, middle) > altitude) == rising
        low, high = (low, middle) if beyond else (middle, high)
    return high


def astronomical_dusk(night: date, site: Site) -> float:
    """Unix time when the Sun sinks below -18° in the evening of ``night`` (local solar time).

    Raises:
        ValueError: the Sun does not reach -18° that night (polar summer) or never rises above it.
    """
    noon = local_noon(night, site.longitude)
    if sun_altitude(site.latitude, site.longitude, noon) <= ASTRONOMICAL_TWILIGHT:
        raise ValueError(
            f"the Sun stays below {ASTRONOMICAL_TWILIGHT}° on {night} at latitude {site.latitude}"
        )
    try:
        return sun_crossing(site, noon, ASTRONOMICAL_TWILIGHT, rising=False, within=18 * 3600.0)
    except ValueError:
        raise ValueError(f"no astronomical night on {night} at latitude {site.latitude}") from None
