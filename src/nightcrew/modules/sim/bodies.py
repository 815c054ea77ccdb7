"""Moving bodies in the simulated sky: how bright each kind is drawn, and what moves during an
exposure (:class:`~nightcrew.sim.render.Motion`) when the mount follows a body or tracks at
offset rates.

The body is where its ephemeris (:func:`nightcrew.astro.ephemeris.positions`) says, at each
sub-time: the simulator's truth is the same ephemeris a user's frames are compared with, so the
measured positions test the measuring, not two ephemerides against each other.
"""

from __future__ import annotations

import math

import numpy as np

from nightcrew.astro.elements import KeplerElements, MajorBody, TwoLineElements
from nightcrew.astro.ephemeris import Body, positions
from nightcrew.sim.render import Motion, MovingBody
from nightcrew.sim.trail import sample_count, sample_fractions
from nightcrew.site import Site

__all__ = [
    "MAJOR_BODY_MAGNITUDES",
    "MINOR_BODY_MAGNITUDE",
    "SATELLITE_MAGNITUDE",
    "body_magnitude",
    "exposure_motion",
]

#: Typical visual magnitudes of the planets and the Moon (they are drawn as points: a planet's
#: disc, 4" to 50", is not modelled, so the bright ones saturate).
MAJOR_BODY_MAGNITUDES: dict[str, float] = {
    "mercury": 0.0,
    "venus": -4.2,
    "moon": -12.0,
    "mars": 0.5,
    "jupiter": -2.5,
    "saturn": 0.6,
    "uranus": 5.7,
    "neptune": 7.8,
    "pluto": 14.4,
}
#: Minor planets and comets (the elements carry no absolute magnitude): bright enough to measure.
MINOR_BODY_MAGNITUDE = 14.0
#: Earth satellites (a small sunlit one: a one-second frame of it does not saturate).
SATELLITE_MAGNITUDE = 8.0


def body_magnitude(body: Body) -> float:
    """The magnitude a body is drawn with."""
    if isinstance(body, MajorBody):
        return MAJOR_BODY_MAGNITUDES[body.name]
    if isinstance(body, TwoLineElements):
        return SATELLITE_MAGNITUDE
    assert isinstance(body, KeplerElements)
    return MINOR_BODY_MAGNITUDE


def exposure_motion(
    *,
    start: float,
    exposure_time: float,
    pointing: tuple[float, float],
    rates: tuple[float, float],
    body: Body | None,
    site: Site,
    pixel_scale_arcsec: float,
) -> Motion | None:
    """What moves during an exposure; None when nothing does (sidereal tracking, no body).

    A mount that follows ``body`` keeps on it: the axis moves with the body, from where it points
    at the start (the follow loop keeps the real mount within its ``follow_error_limit`` by
    updating its rates during the exposure; the simulator draws that following as exact). A mount
    that tracks at offset ``rates`` without a body moves along them.

    Args:
        start: Unix time the shutter opens.
        exposure_time: Seconds it stays open.
        pointing: Where the axis points at the start, ICRS degrees.
        rates: The mount's offset rates, arcsec/s of RA (as an angle of right ascension) and Dec.
        body: The body the mount follows, if any.
        site: Where the telescope stands.
        pixel_scale_arcsec: Unbinned pixel scale: the paths are sampled every quarter pixel.
    """
    if exposure_time <= 0 or (rates == (0.0, 0.0) and body is None):
        return None
    ra0, dec0 = pointing
    cos_dec = math.cos(math.radians(dec0))
    path = math.hypot(rates[0] * cos_dec, rates[1]) * exposure_time
    if body is not None:
        ends = positions(body, site, np.array([start, start + exposure_time]))
        moved_ra = ((ends[0][1] - ends[0][0] + 180.0) % 360.0 - 180.0) * 3600.0
        path = math.hypot(moved_ra * cos_dec, (ends[1][1] - ends[1][0]) * 3600.0)
    seconds = sample_fractions(sample_count(path / pixel_scale_arcsec)) * exposure_time
    if body is None:
        pointing_ra = (ra0 + rates[0] * seconds / 3600.0) % 360.0
        pointing_dec = np.clip(dec0 + rates[1] * seconds / 3600.0, -90.0, 90.0)
        return Motion(pointing_ra=pointing_ra, pointing_dec=pointing_dec)
    ra, dec, _ = positions(body, site, np.concatenate(([start], start + seconds)))
    pointing_ra = (ra0 + ((ra[1:] - ra[0] + 180.0) % 360.0 - 180.0)) % 360.0
    pointing_dec = np.clip(dec0 + dec[1:] - dec[0], -90.0, 90.0)
    body_path = MovingBody(ra=ra[1:], dec=dec[1:], mag=body_magnitude(body))
    return Motion(pointing_ra=pointing_ra, pointing_dec=pointing_dec, bodies=(body_path,))
