"""Coordinates at a site and time, as fast pure functions (no astropy at run time).

ICRS/J2000 (ra, dec) ↔ horizontal (alt, az) with IAU 1976 precession and the IAU 1982 sidereal
time; nutation, aberration and refraction are left out, which keeps the result within about an
arcminute of astropy (see tests/modules/test_coords.py) — plenty for altitude limits, airmass,
dome azimuth and slew times, and ~100x faster than building astropy frames for every call.
All angles in degrees, azimuth east of north, times as Unix seconds (UTC).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

__all__ = [
    "airmass",
    "altaz_to_radec",
    "angular_separation",
    "format_dec",
    "format_ra",
    "julian_date",
    "local_sidereal_time",
    "moon_radec",
    "radec_to_altaz",
]

_J2000 = 2451545.0
_UNIX_EPOCH_JD = 2440587.5
_ARCSEC = 1.0 / 3600.0


def julian_date(unix_time: float) -> float:
    """Julian date of a Unix time (UTC; the ~69 s TT-UTC difference is below our accuracy)."""
    return unix_time / 86400.0 + _UNIX_EPOCH_JD


def local_sidereal_time(unix_time: float, longitude: float) -> float:
    """Local mean sidereal time in degrees (0..360) at east ``longitude``."""
    jd = julian_date(unix_time)
    t = (jd - _J2000) / 36525.0
    gmst = 280.46061837 + 360.98564736629 * (jd - _J2000) + 0.000387933 * t * t - t**3 / 38710000.0
    return (gmst + longitude) % 360.0


def _precession_matrix(unix_time: float) -> npt.NDArray[np.float64]:
    """IAU 1976 precession from J2000 to the mean equator and equinox of date."""
    t = (julian_date(unix_time) - _J2000) / 36525.0
    zeta = math.radians((2306.2181 * t + 0.30188 * t * t + 0.017998 * t**3) * _ARCSEC)
    z = math.radians((2306.2181 * t + 1.09468 * t * t + 0.018203 * t**3) * _ARCSEC)
    theta = math.radians((2004.3109 * t - 0.42665 * t * t - 0.041833 * t**3) * _ARCSEC)
    return _rot_z(-z) @ _rot_y(theta) @ _rot_z(-zeta)


def _rot_z(angle: float) -> npt.NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def _rot_y(angle: float) -> npt.NDArray[np.float64]:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


def _to_vector(lon: float, lat: float) -> npt.NDArray[np.float64]:
    lon_r, lat_r = math.radians(lon), math.radians(lat)
    return np.array([math.cos(lat_r) * math.cos(lon_r), math.cos(lat_r) * math.sin(lon_r), math.sin(lat_r)])


def _from_vector(v: npt.NDArray[np.float64]) -> tuple[float, float]:
    lon = math.degrees(math.atan2(float(v[1]), float(v[0]))) % 360.0
    lat = math.degrees(math.asin(max(-1.0, min(1.0, float(v[2])))))
    return lon, lat


def _rotate_sphere(lat: float, lon: float, pole_lat: float) -> tuple[float, float]:
    """The spherical triangle shared by (dec, hour angle) → (alt, az) and its inverse."""
    phi, b, h = math.radians(pole_lat), math.radians(lat), math.radians(lon)
    sin_out = math.sin(phi) * math.sin(b) + math.cos(phi) * math.cos(b) * math.cos(h)
    out_lat = math.degrees(math.asin(max(-1.0, min(1.0, sin_out))))
    out_lon = math.atan2(
        -math.cos(b) * math.sin(h), math.sin(b) * math.cos(phi) - math.cos(b) * math.sin(phi) * math.cos(h)
    )
    return out_lat, math.degrees(out_lon) % 360.0


def radec_to_altaz(
    ra: float, dec: float, latitude: float, longitude: float, unix_time: float
) -> tuple[float, float]:
    """(alt, az) of ICRS (ra, dec) seen from the site at the time (no refraction)."""
    ra_date, dec_date = _from_vector(_precession_matrix(unix_time) @ _to_vector(ra, dec))
    hour_angle = local_sidereal_time(unix_time, longitude) - ra_date
    return _rotate_sphere(dec_date, hour_angle, latitude)


def altaz_to_radec(
    alt: float, az: float, latitude: float, longitude: float, unix_time: float
) -> tuple[float, float]:
    """ICRS (ra, dec) of the direction (alt, az) at the site and time; inverse of radec_to_altaz."""
    dec_date, hour_angle = _rotate_sphere(alt, az, latitude)
    ra_date = local_sidereal_time(unix_time, longitude) - hour_angle
    return _from_vector(_precession_matrix(unix_time).T @ _to_vector(ra_date, dec_date))


def angular_separation(lon1: float, lat1: float, lon2: float, lat2: float) -> float:
    """Great-circle distance in degrees (Vincenty's formula: exact for tiny and large angles)."""
    l1, b1, l2, b2 = map(math.radians, (lon1, lat1, lon2, lat2))
    dl = l2 - l1
    num = math.hypot(
        math.cos(b2) * math.sin(dl), math.cos(b1) * math.sin(b2) - math.sin(b1) * math.cos(b2) * math.cos(dl)
    )
    den = math.sin(b1) * math.sin(b2) + math.cos(b1) * math.cos(b2) * math.cos(dl)
    return math.degrees(math.atan2(num, den))


def airmass(alt: float) -> float | None:
    """Airmass at altitude ``alt`` (Kasten & Young 1989); None at or below the horizon."""
    if alt <= 0.0:
        return None
    return float(1.0 / (math.sin(math.radians(alt)) + 0.50572 * (alt + 6.07995) ** -1.6364))


def moon_radec(unix_time: float) -> tuple[float, float]:
    """Geocentric ICRS (ra, dec) of the Moon to ~0.3° (low-precision series of the Astronomical
    Almanac); topocentric parallax (up to 1°) is ignored. Good for a moon separation header."""
    t = (julian_date(unix_time) - _J2000) / 36525.0

    def sin_d(x: float) -> float:
        return math.sin(math.radians(x))

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
    obliquity = math.radians(23.439 - 0.0130 * t)
    ecliptic = _to_vector(lon, lat)
    c, s = math.cos(obliquity), math.sin(obliquity)
    equatorial_of_date = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ ecliptic
    return _from_vector(_precession_matrix(unix_time).T @ equatorial_of_date)


def format_ra(ra: float) -> str:
    """Right ascension as 'hh mm ss.ss' (the OBJCTRA convention)."""
    total = round((ra % 360.0) / 15.0 * 3600.0, 2) % 86400.0
    hours, rest = divmod(total, 3600.0)
    minutes, seconds = divmod(rest, 60.0)
    return f"{int(hours):02d} {int(minutes):02d} {seconds:05.2f}"


def format_dec(dec: float) -> str:
    """Declination as '+dd mm ss.s' (the OBJCTDEC convention)."""
    sign = "-" if dec < 0 else "+"
    total = round(abs(dec) * 3600.0, 1)
    degrees, rest = divmod(total, 3600.0)
    minutes, seconds = divmod(rest, 60.0)
    return f"{sign}{int(degrees):02d} {int(minutes):02d} {seconds:04.1f}"
