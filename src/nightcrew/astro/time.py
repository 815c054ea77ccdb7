"""Time scales for the astronomical formulas: Julian date and local sidereal time.

Times are Unix seconds (UTC), one or an array of them; the ~69 s TT-UTC difference is below the
accuracy of :mod:`nightcrew.astro` and is ignored throughout.
"""

from __future__ import annotations

from nightcrew.astro._math import Real

__all__ = [
    "J2000",
    "julian_centuries",
    "julian_date",
    "julian_year",
    "local_sidereal_time",
    "modified_julian_date",
]

#: Julian date of the epoch J2000.0.
J2000 = 2451545.0
_UNIX_EPOCH_JD = 2440587.5
#: The modified Julian date counts days from JD 2400000.5.
_MJD_ZERO_JD = 2400000.5
_DAY = 86400.0


def julian_date(unix_time: Real) -> Real:
    """Julian date of a Unix time."""
    return unix_time / _DAY + _UNIX_EPOCH_JD


def modified_julian_date(unix_time: Real) -> Real:
    """Modified Julian date (JD - 2400000.5) of a Unix time."""
    # The offset in one step: JD - 2400000.5 would round to the JD's 4e-10 d (40 us).
    return unix_time / _DAY + (_UNIX_EPOCH_JD - _MJD_ZERO_JD)


def julian_year(unix_time: Real) -> Real:
    """Julian epoch (2000.0 at J2000, years of 365.25 days) of a Unix time, e.g. for proper motion."""
    return 2000.0 + (julian_date(unix_time) - J2000) / 365.25


def julian_centuries(unix_time: Real) -> Real:
    """Julian centuries since J2000, the time argument of the precession and Moon series."""
    return (julian_date(unix_time) - J2000) / 36525.0


def local_sidereal_time(unix_time: Real, longitude: float) -> Real:
    """Local mean sidereal time in degrees (0..360) at east ``longitude`` (IAU 1982 GMST)."""
    days = julian_date(unix_time) - J2000
    t = days / 36525.0
    gmst = 280.46061837 + 360.98564736629 * days + 0.000387933 * t * t - t**3 / 38710000.0
    return (gmst + longitude) % 360.0
