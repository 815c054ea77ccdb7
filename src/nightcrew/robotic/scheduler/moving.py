"""A moving target for the scheduler: a body followed along its ephemeris.

:class:`EphemerisTarget` is a :class:`~.blocks.Target` whose ``ra``/``dec`` are only a reference
(the position at one moment, for what needs a single position: the block checks and the meridian
estimate); :class:`~.sky.SkyGrid` asks :meth:`EphemerisTarget.track` for the position and altitude
at every slice edge instead, so a body's visibility and Moon distance are evaluated where it is.

Planets, minor planets and comets are computed every :data:`SAMPLE_S` seconds and their (ra, dec)
interpolated to the edges (a fast near-Earth object bends its path by well under an arcminute in
that time), their altitudes then computed as for fixed targets: a full ephemeris at every edge of
500 blocks would cost the scheduler seconds. The samples fall on whole multiples of
:data:`SAMPLE_S` (UTC) and are kept (a bounded cache of pure results): a re-plan of the same night
reuses them, since skyfield's two-body propagation costs some 50 ms a call whatever the number of
times.

A satellite crosses the sky in minutes, between two edges: it is sampled every
:data:`SATELLITE_SAMPLE_S` seconds, and each pass is given to the slice in which it rises above the
horizon, with the pass's highest altitude (and its position then, for the Moon's distance) at both
edges of that slice. A slice counts as visible
when a pass high enough rises in it: a block placed there starts before the pass (some five
minutes: the rise to 30° of a low orbit), and the imaging script waits for the satellite to climb
above the limit. The passes are the satellite's windows.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from nightcrew.astro import radec_to_altaz
from nightcrew.astro.elements import TwoLineElements
from nightcrew.astro.ephemeris import Body, FloatArray, position_at, positions
from nightcrew.robotic.scheduler.blocks import Target
from nightcrew.site import Site

__all__ = ["SAMPLE_S", "SATELLITE_SAMPLE_S", "EphemerisTarget", "Track"]

#: Seconds between the ephemeris samples of a body that is not a satellite.
SAMPLE_S = 1800.0
#: Seconds between the samples of a satellite (a pass above 30° lasts a few minutes).
SATELLITE_SAMPLE_S = 20.0


@dataclass(frozen=True)
class Track:
    """(ra, dec, altitude) in degrees at a series of times."""

    ra: FloatArray
    dec: FloatArray
    altitude: FloatArray


@dataclass(frozen=True, kw_only=True)
class EphemerisTarget(Target):
    """A body (planet, minor planet, comet, satellite) seen from ``site``.

    Args:
        body: What to follow.
        site: Where from: a moving target's position depends on it.
        ra: Reference right ascension (degrees), e.g. at the middle of the first window.
        dec: Reference declination (degrees).
    """

    body: Body
    site: Site

    @classmethod
    def at(cls, body: Body, site: Site, unix_time: float) -> EphemerisTarget:
        """The target with its reference position at ``unix_time`` (from the kept samples: the
        scheduler makes its blocks anew for every plan)."""
        ra, dec = cls(ra=0.0, dec=0.0, body=body, site=site).position_at(unix_time)
        return cls(ra=ra, dec=dec, body=body, site=site)

    def position_at(self, unix_time: float) -> tuple[float, float]:
        """(ra, dec) in degrees at ``unix_time`` along the ephemeris (as :meth:`track` gives it)."""
        if isinstance(self.body, TwoLineElements):
            return position_at(self.body, self.site, unix_time)  # SGP4 is cheap
        found = self.track(np.array([unix_time, unix_time + 1.0]))
        return float(found.ra[0]), float(found.dec[0])

    def track(self, unix_times: FloatArray) -> Track:
        """Position and altitude at every one of ``unix_times`` (Unix seconds, increasing)."""
        times = np.asarray(unix_times, dtype=np.float64)
        if len(times) < 2:
            return Track(*positions(self.body, self.site, times))
        if isinstance(self.body, TwoLineElements):
            return self._satellite_track(times)
        first, last = int(np.floor(times[0] / SAMPLE_S)), int(np.ceil(times[-1] / SAMPLE_S))
        samples = SAMPLE_S * np.arange(first, max(last, first + 1) + 1, dtype=np.float64)
        sample_ra, sample_dec = _sampled(self.body, self.site, first, len(samples))
        ra = np.interp(times, samples, np.unwrap(sample_ra, period=360.0)) % 360.0
        dec = np.interp(times, samples, sample_dec)
        altitude, _ = radec_to_altaz(ra, dec, self.site.latitude, self.site.longitude, times)
        return Track(ra, dec, np.asarray(altitude, dtype=np.float64))

    def _satellite_track(self, edges: FloatArray) -> Track:
        samples = np.arange(edges[0], edges[-1] + SATELLITE_SAMPLE_S, SATELLITE_SAMPLE_S)
        sample_ra, sample_dec, altitude = positions(self.body, self.site, samples)
        up = np.concatenate(([0], (altitude > 0.0).astype(np.int8), [0]))
        rises, sets = np.flatnonzero(np.diff(up) == 1), np.flatnonzero(np.diff(up) == -1)
        edge_altitude = np.full(len(edges), -90.0)
        ra, dec = np.zeros(len(edges)), np.zeros(len(edges))
        for rise, set_ in zip(rises, sets, strict=True):
            index = min(int(np.searchsorted(edges, samples[rise], side="right")) - 1, len(edges) - 2)
            peak = rise + int(np.argmax(altitude[rise:set_]))
            for edge in (index, index + 1):
                if altitude[peak] > edge_altitude[edge]:
                    edge_altitude[edge] = altitude[peak]
                    ra[edge], dec[edge] = sample_ra[peak], sample_dec[peak]
        return Track(ra, dec, edge_altitude)


@functools.lru_cache(maxsize=2048)
def _sampled(body: Body, site: Site, first: int, count: int) -> tuple[FloatArray, FloatArray]:
    """(ra, dec) of ``body`` at ``count`` multiples of :data:`SAMPLE_S` from ``first`` x SAMPLE_S."""
    samples = SAMPLE_S * np.arange(first, first + count, dtype=np.float64)
    ra, dec, _ = positions(body, site, samples)
    return ra, dec
