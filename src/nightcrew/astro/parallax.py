"""Geocentric to topocentric: where a near body appears from a place on the Earth's surface.

The Moon is 60 Earth radii away, so from the surface it appears up to ~1° from its geocentric
position (the Sun: 8.8"). The site's position (WGS84 ellipsoid, with its elevation) is turned with
the local mean sidereal time onto the mean equator of date and precessed back to J2000, where the
body's geocentric position lives; the difference of the two vectors is the body seen from the site.
Nutation and UT1-UTC turn that ~6,400-km vector by less than 20": under 0.0001° of the Moon.
"""

from __future__ import annotations

from nightcrew.astro._math import DEG, Real, elementary
from nightcrew.astro.coords import from_unit_vector, precess, unit_vector
from nightcrew.astro.time import local_sidereal_time
from nightcrew.site import Site

__all__ = ["AU_KM", "EARTH_RADIUS_KM", "topocentric_radec"]

#: The astronomical unit and the WGS84 equatorial radius and flattening.
AU_KM = 149_597_870.7
EARTH_RADIUS_KM = 6378.137
_FLATTENING = 1.0 / 298.257223563


def _site_vector(site: Site, unix_time: Real) -> tuple[Real, Real, Real]:
    """The site's geocentric position in AU, J2000 axes, at the time."""
    xp = elementary(unix_time)
    phi = site.latitude * DEG
    squashed = (1.0 - _FLATTENING) ** 2
    c = 1.0 / xp.hypot(xp.cos(phi), (1.0 - _FLATTENING) * xp.sin(phi))
    height = site.elevation / 1000.0 / EARTH_RADIUS_KM
    # rho cos(phi') and rho sin(phi'), in Earth radii, then AU.
    rho_cos = (c + height) * xp.cos(phi) * EARTH_RADIUS_KM / AU_KM
    rho_sin = (squashed * c + height) * xp.sin(phi) * EARTH_RADIUS_KM / AU_KM
    lst = local_sidereal_time(unix_time, site.longitude) * DEG
    of_date = (rho_cos * xp.cos(lst), rho_cos * xp.sin(lst), rho_sin + 0.0 * lst)
    return precess(of_date, unix_time, xp, inverse=True)


def topocentric_radec(
    ra: Real, dec: Real, distance_au: Real, site: Site, unix_time: Real
) -> tuple[Real, Real]:
    """J2000 (ra, dec) of a body at geocentric (ra, dec, distance) seen from ``site``."""
    xp = elementary(unix_time)
    x, y, z = unit_vector(ra, dec, xp)
    sx, sy, sz = _site_vector(site, unix_time)
    dx, dy, dz = x * distance_au - sx, y * distance_au - sy, z * distance_au - sz
    norm = xp.hypot(xp.hypot(dx, dy), dz)
    return from_unit_vector((dx / norm, dy / norm, dz / norm), xp)
