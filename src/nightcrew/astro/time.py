"""Time scales for the astronomical formulas: Julian date and local sidereal time.

Times are Unix seconds (UTC); the ~69 s TT-UTC difference is below the accuracy of
:mod:`nightcrew.astro` and is ignored throughout.
"""

from __future__ import annotations

__all__ = ["J2000", "julian_centuries", "julian_date", "local_sidereal_time"]

#: Julian date of the epoch J2000.0.
J2000 = 2451545.0
_UNIX_EPOCH_JD = 2440587.5


def julian_date(unix_time: float) -> float:
    """Julian date of a Unix time."""
    return unix_time / 86400.0 + _UNIX_EPOCH_JD


def julian_centuries(unix_time: float) -> float:
    """Julian centuries since J2000, the time argument of the precession and Moon series."""
    return (julian_date(unix_time) - J2000) / 36525.0


def local_sidereal_time(unix_time: float, longitude: float) -> float:
    """Local mean sidereal time in degrees (0..360) at east ``longitude`` (IAU 1982 GMST)."""
    days = julian_date(unix_time) - J2000
    t = days / 36525.0
    gmst = 280.46061837 + 360.98564736629 * days + 0.000387933 * t * t - t**3 / 38710000.0
    return (gmst + longitude) % 360.0
