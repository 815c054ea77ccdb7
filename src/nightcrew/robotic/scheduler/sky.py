"""The night on a time grid: Sun, Moon and target altitudes at every grid edge, as arrays.

The night is cut into equal *slices* of ``step`` seconds; slice ``i`` covers
``[start + i*step, start + (i+1)*step]``. Sky quantities are sampled at the ``n + 1`` slice edges,
and a constraint holds on a slice when it holds at both its edges (within 5 minutes altitude and
separation change monotonically, so this is exact up to turning points).

Sun and Moon come from the simulator's ephemeris (:mod:`nightcrew.modules.sim.ephemeris`, Moon to
~0.3°, geocentric). Target altitudes use the IAU 1976 precession at mid-night (erfa) and the
sidereal time of :mod:`nightcrew.modules.telescope.coords`, vectorised over targets and edges;
nutation and refraction are left out, as in ``coords`` (about an arcminute).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import erfa  # type: ignore[import-untyped]
import numpy as np
import numpy.typing as npt

from nightcrew.errors import InvalidArgumentError
from nightcrew.modules.sim.ephemeris import moon_illumination, sun_altitude
from nightcrew.modules.telescope.coords import julian_date, local_sidereal_time, moon_radec
from nightcrew.robotic.scheduler.blocks import SchedulableBlock
from nightcrew.site import Site

__all__ = ["SkyGrid", "TimeGrid", "separation"]

FloatArray = npt.NDArray[np.float64]
#: TT - UTC in seconds (32.184 + 37 leap seconds since 2017); precession barely notices an error.
_TT_MINUS_UTC = 69.184


@dataclass(frozen=True)
class TimeGrid:
    """``n_slices`` equal slices of ``step`` seconds from ``start`` (Unix seconds)."""

    start: float
    step: float
    n_slices: int

    @classmethod
    def covering(cls, start: float, end: float, step: float) -> TimeGrid:
        """The slices that fit whole into ``[start, end]``."""
        if not step > 0:
            raise InvalidArgumentError(f"time step must be > 0 s, got {step}")
        return cls(start, step, max(0, math.floor((end - start) / step + 1e-9)))

    @property
    def edges(self) -> FloatArray:
        """Unix times of the ``n_slices + 1`` slice edges."""
        return self.start + self.step * np.arange(self.n_slices + 1, dtype=np.float64)

    def slices_for(self, seconds: float) -> int:
        """Whole slices needed to hold ``seconds`` (rounded up)."""
        return max(1, math.ceil(seconds / self.step - 1e-9))


def separation(ra1: FloatArray, dec1: FloatArray, ra2: FloatArray, dec2: FloatArray) -> FloatArray:
    """Great-circle distance in degrees, broadcasting (haversine: well conditioned at small angles)."""
    r1, d1, r2, d2 = (np.radians(a) for a in (ra1, dec1, ra2, dec2))
    h = np.sin((d2 - d1) / 2) ** 2 + np.cos(d1) * np.cos(d2) * np.sin((r2 - r1) / 2) ** 2
    return np.asarray(np.degrees(2 * np.arcsin(np.sqrt(np.clip(h, 0.0, 1.0)))), dtype=np.float64)


class SkyGrid:
    """Everything the constraints need about one night and one list of blocks, computed once.

    Args:
        grid: The slices of the night.
        site: Where the telescope stands.
        blocks: The blocks whose targets to follow; row ``k`` of :attr:`altitude` is ``blocks[k]``.
    """

    def __init__(self, grid: TimeGrid, site: Site, blocks: Sequence[SchedulableBlock]) -> None:
        self.grid = grid
        self.site = site
        self.blocks = tuple(blocks)
        edges = grid.edges
        self.edges = edges
        lat, lon = site.latitude, site.longitude
        self.sun_altitude = np.array([sun_altitude(lat, lon, float(t)) for t in edges])
        moon = np.array([moon_radec(float(t)) for t in edges]).reshape(-1, 2)
        self.moon_ra, self.moon_dec = moon[:, 0], moon[:, 1]
        self.moon_illumination = np.array([moon_illumination(float(t)) for t in edges])
        middle = grid.start + grid.step * grid.n_slices / 2
        positions = np.array([b.target.position_at(middle) for b in self.blocks]).reshape(-1, 2)
        self.target_ra, self.target_dec = positions[:, 0], positions[:, 1]
        self.altitude = self._altitudes(middle)

    def _altitudes(self, middle: float) -> FloatArray:
        """Altitude of every target at every edge, shape (n_blocks, n_slices + 1)."""
        ra, dec = np.radians(self.target_ra), np.radians(self.target_dec)
        vectors = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)])
        # Precession over one night changes positions by < 0.1": one matrix at mid-night will do.
        precession = erfa.pmat76(julian_date(middle + _TT_MINUS_UTC), 0.0)
        of_date = precession @ vectors
        ra_date = np.arctan2(of_date[1], of_date[0])
        dec_date = np.arcsin(np.clip(of_date[2], -1.0, 1.0))
        lst = np.radians([local_sidereal_time(float(t), self.site.longitude) for t in self.edges])
        hour_angle = lst[np.newaxis, :] - ra_date[:, np.newaxis]
        phi = math.radians(self.site.latitude)
        sin_alt = math.sin(phi) * np.sin(dec_date)[:, np.newaxis] + math.cos(phi) * np.cos(dec_date)[
            :, np.newaxis
        ] * np.cos(hour_angle)
        return np.asarray(np.degrees(np.arcsin(np.clip(sin_alt, -1.0, 1.0))), dtype=np.float64)

    def moon_distance(self) -> FloatArray:
        """Separation of every target from the Moon at every edge, shape (n_blocks, n_slices + 1)."""
        return separation(
            self.target_ra[:, np.newaxis],
            self.target_dec[:, np.newaxis],
            self.moon_ra[np.newaxis, :],
            self.moon_dec[np.newaxis, :],
        )
