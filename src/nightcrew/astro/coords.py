"""Coordinates at a site and time, as fast pure functions (no astropy at run time).

ICRS/J2000 (ra, dec) ↔ horizontal (alt, az) with IAU 1976 precession and the IAU 1982 sidereal
time; nutation, aberration and refraction are left out, which keeps the result within about an
arcminute of astropy (see tests/astro/test_coords.py) — plenty for altitude limits, airmass,
dome azimuth and slew times, and ~100x faster than building astropy frames for every call.
Each formula is written once over :data:`~nightcrew.astro._math.Real`: a single position runs it
on floats through ``math``, arrays of positions and times through numpy (see
:mod:`nightcrew.astro._math`). All angles in degrees, azimuth east of north, times as Unix
seconds (UTC).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from nightcrew.astro._math import ARRAY, DEG, SCALAR, Elementary, FloatArray, Real, elementary
from nightcrew.astro.time import julian_centuries, local_sidereal_time

__all__ = [
    "Vector",
    "airmass",
    "altaz_to_radec",
    "altitudes",
    "angular_separation",
    "ecliptic_to_equatorial",
    "format_dec",
    "format_ra",
    "from_unit_vector",
    "j2000_to_of_date",
    "of_date_to_j2000",
    "precess",
    "precession_matrix",
    "radec_to_altaz",
    "separation",
    "unit_vector",
]

#: Cartesian (x, y, z), each a number or an array of one shape.
Vector = tuple[Real, Real, Real]
_Matrix = tuple[Vector[Real], Vector[Real], Vector[Real]]
_ARCSEC = DEG / 3600.0


def _precession(unix_time: Real, xp: Elementary[Real]) -> _Matrix[Real]:
    """IAU 1976 precession from J2000 to the mean equator and equinox of date, as the rows of
    Rz(-z) Ry(theta) Rz(-zeta) multiplied out (each element a number or an array over time)."""
    t = julian_centuries(unix_time)
    zeta = (2306.2181 * t + 0.30188 * t * t + 0.017998 * t**3) * _ARCSEC
    z = (2306.2181 * t + 1.09468 * t * t + 0.018203 * t**3) * _ARCSEC
    theta = (2004.3109 * t - 0.42665 * t * t - 0.041833 * t**3) * _ARCSEC
    c_zeta, s_zeta, c_z, s_z = xp.cos(zeta), xp.sin(zeta), xp.cos(z), xp.sin(z)
    c_th, s_th = xp.cos(theta), xp.sin(theta)
    return (
        (c_z * c_th * c_zeta - s_z * s_zeta, -c_z * c_th * s_zeta - s_z * c_zeta, -c_z * s_th),
        (s_z * c_th * c_zeta + c_z * s_zeta, -s_z * c_th * s_zeta + c_z * c_zeta, -s_z * s_th),
        (s_th * c_zeta, -s_th * s_zeta, c_th),
    )


def precession_matrix(unix_time: float) -> FloatArray:
    """IAU 1976 precession from J2000 to the mean equator and equinox of date (3x3)."""
    return np.array(_precession(float(unix_time), SCALAR))


def precess(v: Vector[Real], unix_time: Real, xp: Elementary[Real], *, inverse: bool = False) -> Vector[Real]:
    """``v`` (J2000) on the mean equator of date, or back with ``inverse`` (the transpose)."""
    (a, b, c), (d, e, f), (g, h, i) = _precession(unix_time, xp)
    x, y, z = v
    if inverse:
        return a * x + d * y + g * z, b * x + e * y + h * z, c * x + f * y + i * z
    return a * x + b * y + c * z, d * x + e * y + f * z, g * x + h * y + i * z


def unit_vector(lon: Real, lat: Real | float, xp: Elementary[Real]) -> Vector[Real]:
    """Cartesian unit vector of spherical (lon, lat)."""
    lon_r, lat_r = lon * DEG, lat * DEG
    cos_lat = xp.cos(lat_r)
    return cos_lat * xp.cos(lon_r), cos_lat * xp.sin(lon_r), xp.sin(lat_r)


def from_unit_vector(v: Vector[Real], xp: Elementary[Real]) -> tuple[Real, Real]:
    """(lon 0..360, lat) of a unit vector; inverse of :func:`unit_vector`."""
    return xp.atan2(v[1], v[0]) / DEG % 360.0, xp.asin(v[2]) / DEG


def _rotate_sphere(lat: Real, lon: Real, pole_lat: float, xp: Elementary[Real]) -> tuple[Real, Real]:
    """The spherical triangle shared by (dec, hour angle) → (alt, az) and its inverse."""
    b, h = lat * DEG, lon * DEG
    sin_b, cos_b, cos_h = xp.sin(b), xp.cos(b), xp.cos(h)
    sin_phi, cos_phi = math.sin(pole_lat * DEG), math.cos(pole_lat * DEG)
    out_lon = xp.atan2(-cos_b * xp.sin(h), sin_b * cos_phi - cos_b * sin_phi * cos_h)
    return _rotated_latitude(sin_b, cos_b, cos_h, pole_lat, xp), out_lon / DEG % 360.0


def _rotated_latitude(sin_b: Real, cos_b: Real, cos_h: Real, pole_lat: float, xp: Elementary[Real]) -> Real:
    """The latitude part of :func:`_rotate_sphere` alone (the altitude grid needs no azimuth)."""
    phi = pole_lat * DEG
    return xp.asin(math.sin(phi) * sin_b + math.cos(phi) * cos_b * cos_h) / DEG


def radec_to_altaz(
    ra: Real, dec: Real, latitude: float, longitude: float, unix_time: Real
) -> tuple[Real, Real]:
    """(alt, az) of ICRS (ra, dec) seen from the site at the time (no refraction).

    Floats give floats; arrays (of times, and positions of the same shape or broadcasting) give
    arrays, in one call.
    """
    xp = elementary(unix_time)
    ra_date, dec_date = from_unit_vector(precess(unit_vector(ra, dec, xp), unix_time, xp), xp)
    hour_angle = local_sidereal_time(unix_time, longitude) - ra_date
    return _rotate_sphere(dec_date, hour_angle, latitude, xp)


def altitudes(
    ra: FloatArray, dec: FloatArray, latitude: float, longitude: float, times: FloatArray
) -> FloatArray:
    """Altitude of every ICRS (ra, dec) at every Unix time, shape ``(len(ra), len(times))``.

    One precession, at the middle of ``times``: over a night it moves positions by < 0.1".
    """
    middle = np.asarray(float(times[0] + times[-1]) / 2.0 if len(times) else 0.0)
    ra_date, dec_date = from_unit_vector(precess(unit_vector(ra, dec, ARRAY), middle, ARRAY), ARRAY)
    lst = local_sidereal_time(np.asarray(times, dtype=np.float64), longitude)
    cos_h = np.cos((lst[np.newaxis, :] - ra_date[:, np.newaxis]) * DEG)
    dec_r = dec_date[:, np.newaxis] * DEG
    return np.asarray(
        _rotated_latitude(np.sin(dec_r), np.cos(dec_r), cos_h, latitude, ARRAY), dtype=np.float64
    )


def altaz_to_radec(
    alt: Real, az: Real, latitude: float, longitude: float, unix_time: Real
) -> tuple[Real, Real]:
    """ICRS (ra, dec) of the direction (alt, az) at the site and time; inverse of radec_to_altaz."""
    xp = elementary(unix_time)
    dec_date, hour_angle = _rotate_sphere(alt, az, latitude, xp)
    ra_date = local_sidereal_time(unix_time, longitude) - hour_angle
    return from_unit_vector(precess(unit_vector(ra_date, dec_date, xp), unix_time, xp, inverse=True), xp)


def j2000_to_of_date(ra: float, dec: float, unix_time: float) -> tuple[float, float]:
    """(ra, dec) on the mean equator and equinox of date (INDI's "JNow") of J2000/ICRS (ra, dec)."""
    return from_unit_vector(precess(unit_vector(ra, dec, SCALAR), unix_time, SCALAR), SCALAR)


def of_date_to_j2000(ra: float, dec: float, unix_time: float) -> tuple[float, float]:
    """J2000/ICRS (ra, dec) of a position on the mean equator of date; inverse of j2000_to_of_date."""
    v = precess(unit_vector(ra, dec, SCALAR), unix_time, SCALAR, inverse=True)
    return from_unit_vector(v, SCALAR)


def ecliptic_to_equatorial(
    lon: Real, lat: Real | float, obliquity: Real, xp: Elementary[Real]
) -> Vector[Real]:
    """Unit vector on the equator of date of ecliptic (lon, lat), for an ``obliquity`` in degrees."""
    x, y, z = unit_vector(lon, lat, xp)
    c, s = xp.cos(obliquity * DEG), xp.sin(obliquity * DEG)
    return x, c * y - s * z, s * y + c * z


def angular_separation(lon1: Real, lat1: Real, lon2: Real, lat2: Real) -> Real:
    """Great-circle distance in degrees (Vincenty's formula: exact for tiny and large angles);
    floats give a float, arrays (of one shape) an array."""
    xp = elementary(lon1)
    b1, b2, dl = lat1 * DEG, lat2 * DEG, (lon2 - lon1) * DEG
    sin_b1, cos_b1, sin_b2, cos_b2, cos_dl = xp.sin(b1), xp.cos(b1), xp.sin(b2), xp.cos(b2), xp.cos(dl)
    num = xp.hypot(cos_b2 * xp.sin(dl), cos_b1 * sin_b2 - sin_b1 * cos_b2 * cos_dl)
    return xp.atan2(num, sin_b1 * sin_b2 + cos_b1 * cos_b2 * cos_dl) / DEG


def separation(
    lon1: npt.ArrayLike, lat1: npt.ArrayLike, lon2: npt.ArrayLike, lat2: npt.ArrayLike
) -> FloatArray:
    """Great-circle distances in degrees of anything that broadcasts (:func:`angular_separation`)."""
    l1, b1, l2, b2 = (np.asarray(a, dtype=np.float64) for a in (lon1, lat1, lon2, lat2))
    return np.asarray(angular_separation(l1, b1, l2, b2), dtype=np.float64)


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
