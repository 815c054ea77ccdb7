"""Coordinates at a site and time, as fast pure functions (no astropy at run time).

ICRS/J2000 (ra, dec) ↔ horizontal (alt, az) with IAU 1976 precession and the IAU 1982 sidereal
time; nutation, aberration and refraction are left out, which keeps the result within about an
arcminute of astropy (see tests/astro/test_coords.py) — plenty for altitude limits, airmass,
dome azimuth and slew times, and ~100x faster than building astropy frames for every call.
The spherical formulas broadcast over numpy arrays, so the scheduler's grids of targets and times
use the same code as a single position. All angles in degrees, azimuth east of north, times as
Unix seconds (UTC).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from nightcrew.astro.time import julian_centuries, local_sidereal_time

__all__ = [
    "airmass",
    "altaz_to_radec",
    "altitudes",
    "angular_separation",
    "ecliptic_to_equatorial",
    "format_dec",
    "format_ra",
    "from_unit_vector",
    "precession_matrix",
    "radec_to_altaz",
    "separation",
    "unit_vector",
]

FloatArray = npt.NDArray[np.float64]
_ARCSEC = 1.0 / 3600.0


def precession_matrix(unix_time: float) -> FloatArray:
    """IAU 1976 precession from J2000 to the mean equator and equinox of date (3x3)."""
    t = julian_centuries(unix_time)
    zeta = math.radians((2306.2181 * t + 0.30188 * t * t + 0.017998 * t**3) * _ARCSEC)
    z = math.radians((2306.2181 * t + 1.09468 * t * t + 0.018203 * t**3) * _ARCSEC)
    theta = math.radians((2004.3109 * t - 0.42665 * t * t - 0.041833 * t**3) * _ARCSEC)
    return _rot_z(-z) @ _rot_y(theta) @ _rot_z(-zeta)


def _rot_y(angle: float) -> FloatArray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


def _rot_z(angle: float) -> FloatArray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def unit_vector(lon: npt.ArrayLike, lat: npt.ArrayLike) -> FloatArray:
    """Cartesian unit vectors of spherical (lon, lat) of one shape, shape ``(3, *that shape)``."""
    lon_r, lat_r = np.radians(lon), np.radians(lat)
    cos_lat = np.cos(lat_r)
    return np.array([cos_lat * np.cos(lon_r), cos_lat * np.sin(lon_r), np.sin(lat_r)])


def from_unit_vector(v: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(lon 0..360, lat) of vectors along the first axis; inverse of :func:`unit_vector`."""
    return np.degrees(np.arctan2(v[1], v[0])) % 360.0, _asin_degrees(v[2])


def _asin_degrees(x: npt.ArrayLike) -> FloatArray:
    # Clipped: rounding can take a sine of ±1 a bit beyond. np.clip costs twice as much on scalars.
    return np.asarray(np.degrees(np.arcsin(np.minimum(1.0, np.maximum(-1.0, x)))))


def _rotate_sphere(lat: npt.ArrayLike, lon: npt.ArrayLike, pole_lat: float) -> tuple[FloatArray, FloatArray]:
    """The spherical triangle shared by (dec, hour angle) → (alt, az) and its inverse."""
    phi, b, h = math.radians(pole_lat), np.radians(lat), np.radians(lon)
    sin_phi, cos_phi = math.sin(phi), math.cos(phi)
    sin_b, cos_b, cos_h = np.sin(b), np.cos(b), np.cos(h)
    out_lat = _asin_degrees(sin_phi * sin_b + cos_phi * cos_b * cos_h)
    out_lon = np.arctan2(-cos_b * np.sin(h), sin_b * cos_phi - cos_b * sin_phi * cos_h)
    return out_lat, np.degrees(out_lon) % 360.0


def radec_to_altaz(
    ra: float, dec: float, latitude: float, longitude: float, unix_time: float
) -> tuple[float, float]:
    """(alt, az) of ICRS (ra, dec) seen from the site at the time (no refraction)."""
    ra_date, dec_date = from_unit_vector(precession_matrix(unix_time) @ unit_vector(ra, dec))
    hour_angle = local_sidereal_time(unix_time, longitude) - ra_date
    alt, az = _rotate_sphere(dec_date, hour_angle, latitude)
    return float(alt), float(az)


def altitudes(
    ra: FloatArray, dec: FloatArray, latitude: float, longitude: float, times: FloatArray
) -> FloatArray:
    """Altitude of every ICRS (ra, dec) at every Unix time, shape ``(len(ra), len(times))``.

    One precession, at the middle of ``times``: over a night it moves positions by < 0.1".
    """
    middle = float(times[0] + times[-1]) / 2.0 if len(times) else 0.0
    ra_date, dec_date = from_unit_vector(precession_matrix(middle) @ unit_vector(ra, dec))
    lst = np.array([local_sidereal_time(float(t), longitude) for t in times], dtype=np.float64)
    alt, _ = _rotate_sphere(dec_date[:, np.newaxis], lst[np.newaxis, :] - ra_date[:, np.newaxis], latitude)
    return np.asarray(alt, dtype=np.float64)


def altaz_to_radec(
    alt: float, az: float, latitude: float, longitude: float, unix_time: float
) -> tuple[float, float]:
    """ICRS (ra, dec) of the direction (alt, az) at the site and time; inverse of radec_to_altaz."""
    dec_date, hour_angle = _rotate_sphere(alt, az, latitude)
    ra_date = local_sidereal_time(unix_time, longitude) - hour_angle
    ra, dec = from_unit_vector(precession_matrix(unix_time).T @ unit_vector(ra_date, dec_date))
    return float(ra), float(dec)


def ecliptic_to_equatorial(lon: float, lat: float, obliquity: float) -> FloatArray:
    """Unit vector on the equator of date of ecliptic (lon, lat), for an ``obliquity`` in degrees."""
    c, s = math.cos(math.radians(obliquity)), math.sin(math.radians(obliquity))
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]) @ unit_vector(lon, lat)


def separation(
    lon1: npt.ArrayLike, lat1: npt.ArrayLike, lon2: npt.ArrayLike, lat2: npt.ArrayLike
) -> FloatArray:
    """Great-circle distance in degrees, broadcasting (Vincenty's formula: exact for tiny and large
    angles)."""
    l1, b1, l2, b2 = (np.radians(a) for a in (lon1, lat1, lon2, lat2))
    dl = l2 - l1
    num = np.hypot(np.cos(b2) * np.sin(dl), np.cos(b1) * np.sin(b2) - np.sin(b1) * np.cos(b2) * np.cos(dl))
    den = np.sin(b1) * np.sin(b2) + np.cos(b1) * np.cos(b2) * np.cos(dl)
    return np.asarray(np.degrees(np.arctan2(num, den)), dtype=np.float64)


def angular_separation(lon1: float, lat1: float, lon2: float, lat2: float) -> float:
    """Great-circle distance in degrees between two points (:func:`separation` for one pair)."""
    return float(separation(lon1, lat1, lon2, lat2))


def airmass(alt: float) -> float | None:
    """Airmass at altitude ``alt`` (Kasten & Young 1989); None at or below the horizon."""
    if alt <= 0.0:
        return None
    return float(1.0 / (math.sin(math.radians(alt)) + 0.50572 * (alt + 6.07995) ** -1.6364))


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
