"""Where a moving target is seen from the site: topocentric positions and rates, offline.

Computed with skyfield: planets and the Moon from the JPL DE421 kernel that the ``skyfield-data``
package ships (nothing is downloaded), minor planets and comets as two-body orbits around the Sun
(skyfield's MPC orbits), Earth satellites with SGP4 (through skyfield). Time scales use skyfield's
built-in leap-second and Delta-T tables, so no file is fetched either.

:func:`ephemeris` gives, at each of an array of times, the target's topocentric right ascension
and declination, its rates, altitude, azimuth and distance. Two kinds of position:

- *astrometric* (the default): light time applied, axes and aberration as for catalogue stars
  (ICRS). This is where the body stands among the stars of a catalogue, so it is what a mount
  pointed by catalogue coordinates is sent to, what a plate solution measures, and what the MPC
  expects in an observation.
- *apparent* (``apparent=True``): also the aberration and the light deflection skyfield applies,
  still on ICRS axes (GCRS); what astropy's ``get_body`` gives, which :mod:`bench.moving` compares.

Satellites are near enough that light time and aberration are below a metre; their position is
the geometric topocentric one either way. Pure: no clock, no I/O beyond reading the packaged kernel
once (kept for the process, as the kernel does not change).
"""

from __future__ import annotations

import functools
import importlib.resources
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from nightcrew.astro.elements import MAJOR_BODIES, KeplerElements, MajorBody, TwoLineElements
from nightcrew.site import Site

__all__ = ["Body", "Ephemeris", "ephemeris", "next_rise", "position_at", "positions"]

FloatArray = npt.NDArray[np.float64]
#: What an ephemeris can be computed for.
Body = MajorBody | KeplerElements | TwoLineElements

_SECONDS_PER_DAY = 86_400.0
#: Half the time step of the central difference that gives the rates (seconds): short enough for a
#: satellite's curved path, long enough that float rounding stays below 1e-6 arcsec/s.
_RATE_HALF_STEP = 0.5


@dataclass(frozen=True)
class Ephemeris:
    """A target's topocentric positions at a series of times (every array has the times' shape).

    Attributes:
        unix_time: The times, Unix seconds (UTC).
        ra: Right ascension, degrees 0..360.
        dec: Declination, degrees.
        ra_rate: d(ra)/dt x cos(dec), arcseconds per second (on the sky).
        dec_rate: d(dec)/dt, arcseconds per second.
        altitude: Degrees above the horizon (geometric, no refraction).
        azimuth: Degrees east of north.
        distance_km: From the site.
    """

    unix_time: FloatArray
    ra: FloatArray
    dec: FloatArray
    ra_rate: FloatArray
    dec_rate: FloatArray
    altitude: FloatArray
    azimuth: FloatArray
    distance_km: FloatArray

    @property
    def rate(self) -> FloatArray:
        """Total motion on the sky, arcseconds per second."""
        return np.asarray(np.hypot(self.ra_rate, self.dec_rate), dtype=np.float64)


def ephemeris(body: Body, site: Site, unix_time: float | FloatArray, *, apparent: bool = False) -> Ephemeris:
    """Topocentric positions and rates of ``body`` seen from ``site`` at ``unix_time``.

    Args:
        body: What to follow.
        site: Where from (geodetic latitude, longitude, height above sea level, WGS84).
        unix_time: One time or an array of times, Unix seconds.
        apparent: Apparent instead of astrometric positions (see the module docstring).
    """
    times = np.atleast_1d(np.asarray(unix_time, dtype=np.float64))
    shape = times.shape
    flat = times.ravel()
    n = flat.size
    # One vectorised call for the times and the two sides of each rate's central difference.
    stacked = np.concatenate((flat, flat - _RATE_HALF_STEP, flat + _RATE_HALF_STEP))
    ra, dec, distance, alt, az = _positions(body, site, stacked, apparent=apparent)
    ra_rate, dec_rate = _rates(ra[n : 2 * n], dec[n : 2 * n], ra[2 * n :], dec[2 * n :], dec[:n])

    def shaped(values: FloatArray) -> FloatArray:
        return np.asarray(values, dtype=np.float64).reshape(shape)

    return Ephemeris(
        unix_time=shaped(flat),
        ra=shaped(ra[:n]),
        dec=shaped(dec[:n]),
        ra_rate=shaped(ra_rate),
        dec_rate=shaped(dec_rate),
        altitude=shaped(alt[:n]),
        azimuth=shaped(az[:n]),
        distance_km=shaped(distance[:n]),
    )


def positions(body: Body, site: Site, unix_time: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Astrometric topocentric (ra, dec) and altitude in degrees at each of ``unix_time``, without
    rates: a third of :func:`ephemeris`'s work, for a scheduler sampling many bodies."""
    ra, dec, _, alt, _ = _positions(
        body, site, np.atleast_1d(np.asarray(unix_time, dtype=np.float64)), apparent=False
    )
    return ra, dec, alt


def next_rise(
    body: Body, site: Site, start: float, altitude: float, *, within: float = 900.0, step: float = 5.0
) -> float | None:
    """The first time from ``start`` (to ``step`` seconds, within ``within`` seconds) at which
    ``body`` stands at or above ``altitude`` degrees; None if it does not."""
    times = start + np.arange(0.0, within + step, step)
    _, _, alt = positions(body, site, times)
    above = np.flatnonzero(alt >= altitude)
    return float(times[above[0]]) if len(above) else None


def position_at(body: Body, site: Site, unix_time: float) -> tuple[float, float]:
    """Astrometric topocentric (ra, dec) in degrees of ``body`` at one time."""
    ra, dec, _ = positions(body, site, np.array([unix_time]))
    return float(ra[0]), float(dec[0])


def _rates(
    ra_before: FloatArray,
    dec_before: FloatArray,
    ra_after: FloatArray,
    dec_after: FloatArray,
    dec: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    step = 2.0 * _RATE_HALF_STEP
    d_ra = (ra_after - ra_before + 180.0) % 360.0 - 180.0
    ra_rate = d_ra * np.cos(np.radians(dec)) * 3600.0 / step
    dec_rate = (dec_after - dec_before) * 3600.0 / step
    return np.asarray(ra_rate, dtype=np.float64), np.asarray(dec_rate, dtype=np.float64)


def _positions(
    body: Body, site: Site, unix_time: FloatArray, *, apparent: bool
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    t = _times(unix_time)
    topos, observer = _observer(site)
    if isinstance(body, TwoLineElements):
        position: Any = (_satellite(body) - topos).at(t)
        seen = position
    else:
        target = _kernel()[MAJOR_BODIES[body.name]] if isinstance(body, MajorBody) else _orbit(body)
        position = observer.at(t).observe(target)
        # Altitude and azimuth need the apparent place (skyfield refuses an astrometric one).
        seen = position.apparent()
        if apparent:
            position = seen
    ra, dec, distance = position.radec()
    alt, az, _ = seen.altaz()
    return (
        np.asarray(ra.degrees, dtype=np.float64) % 360.0,
        np.asarray(dec.degrees, dtype=np.float64),
        np.asarray(distance.km, dtype=np.float64),
        np.asarray(alt.degrees, dtype=np.float64),
        np.asarray(az.degrees, dtype=np.float64),
    )


@functools.cache
def _observer(site: Site) -> tuple[Any, Any]:
    """The site on the WGS84 ellipsoid, and the same seen from the solar system's barycentre."""
    from skyfield.api import wgs84

    topos = wgs84.latlon(site.latitude, site.longitude, elevation_m=site.elevation)
    return topos, _kernel()["earth"] + topos


def _times(unix_time: FloatArray) -> Any:
    # Whole UTC days plus seconds: Unix time has no leap seconds, so each day is 86,400 s long.
    days = np.floor(unix_time / _SECONDS_PER_DAY)
    seconds = unix_time - days * _SECONDS_PER_DAY
    return _timescale().utc(1970, 1, 1 + days, 0, 0, seconds)


@functools.cache
def _kernel() -> Any:
    from skyfield.api import Loader

    # The path of the packaged kernel (skyfield_data's own helper warns about its Earth-orientation
    # file ageing, which is not used here: time scales are skyfield's built-in ones).
    directory = importlib.resources.files("skyfield_data") / "data"
    return Loader(str(directory), verbose=False, expire=False)("de421.bsp")


@functools.cache
def _timescale() -> Any:
    from skyfield.api import load

    return load.timescale(builtin=True)


@functools.cache
def _orbit(elements: KeplerElements) -> Any:
    import pandas as pd
    from skyfield.constants import GM_SUN_Pitjeva_2005_km3_s2
    from skyfield.data.mpc import comet_orbit

    # skyfield's comet orbit takes the perihelion time as a calendar date; a day count from
    # 2000 January 0.0 TT is one (its calendar arithmetic carries the days over).
    day = elements.perihelion_time_jd - 2_451_543.5
    row = pd.Series(
        {
            "designation": elements.name,
            "perihelion_year": 2000,
            "perihelion_month": 1,
            "perihelion_day": day,
            "perihelion_distance_au": elements.perihelion_distance_au,
            "eccentricity": elements.eccentricity,
            "argument_of_perihelion_degrees": elements.argument_of_perihelion,
            "longitude_of_ascending_node_degrees": elements.longitude_of_ascending_node,
            "inclination_degrees": elements.inclination,
        }
    )
    return _kernel()["sun"] + comet_orbit(row, _timescale(), GM_SUN_Pitjeva_2005_km3_s2)


@functools.cache
def _satellite(elements: TwoLineElements) -> Any:
    from skyfield.api import EarthSatellite

    return EarthSatellite(elements.line1, elements.line2, elements.name, _timescale())
