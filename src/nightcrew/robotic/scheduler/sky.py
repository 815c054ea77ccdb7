"""The night on a time grid: Sun, Moon and target altitudes at every grid edge, as arrays.

The night is cut into equal *slices* of ``step`` seconds; slice ``i`` covers
``[start + i*step, start + (i+1)*step]``. Sky quantities are sampled at the ``n + 1`` slice edges,
and a constraint holds on a slice when it holds at both its edges (within 5 minutes altitude and
separation change monotonically, so this is exact up to turning points).

Sun, Moon and target altitudes come from :mod:`nightcrew.astro` (Moon to ~0.3°, geocentric; targets
to about an arcminute), each in one array call over the edges (targets: over targets and edges,
with one precession at mid-night).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nightcrew.astro import altitudes, moon_illumination, moon_radec, separation, sun_altitude
from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.scheduler.blocks import SchedulableBlock
from nightcrew.robotic.scheduler.moving import EphemerisTarget
from nightcrew.site import Site

__all__ = ["GridFit", "SkyGrid", "TimeGrid"]

FloatArray = npt.NDArray[np.float64]


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


class GridFit:
    """How the scheduler lays blocks out, so that a block can be made to fit an interval.

    Args:
        step_s: The scheduler's time slice, seconds (a block starts on a slice edge).
        slew_overhead_s: What the scheduler adds in front of every block, seconds.
    """

    def __init__(self, step_s: float = 300.0, slew_overhead_s: float = 100.0) -> None:
        self.step_s = step_s
        self.slew_overhead_s = slew_overhead_s

    def longest_duration(self, interval_s: float, setup_s: float) -> float:
        """The longest block duration that fits into any interval of ``interval_s`` seconds.

        An interval holds at least ``floor(interval / step) - 1`` whole slices wherever the grid
        starts; the block occupies set-up, slew and its duration, rounded up to whole slices.
        """
        slices = math.floor(interval_s / self.step_s + 1e-9) - 1
        return slices * self.step_s - setup_s - self.slew_overhead_s


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
        self.sun_altitude = sun_altitude(lat, lon, edges)
        self.moon_ra, self.moon_dec = moon_radec(edges)
        self.moon_illumination = moon_illumination(edges)
        middle = grid.start + grid.step * grid.n_slices / 2
        positions = np.array([b.target.position_at(middle) for b in self.blocks]).reshape(-1, 2)
        self.target_ra, self.target_dec = positions[:, 0], positions[:, 1]
        self.altitude = altitudes(self.target_ra, self.target_dec, lat, lon, edges)
        """Altitude of every target at every edge, shape (n_blocks, n_slices + 1)."""
        # Moving targets: the rows above are for their reference position; follow the ephemeris.
        self._tracks: dict[int, tuple[FloatArray, FloatArray]] = {}
        for row, block in enumerate(self.blocks):
            if isinstance(block.target, EphemerisTarget):
                track = block.target.track(edges)
                self.altitude[row] = track.altitude
                self._tracks[row] = (track.ra, track.dec)

    def moon_distance(self) -> FloatArray:
        """Separation of every target from the Moon at every edge, shape (n_blocks, n_slices + 1)."""
        distance = separation(
            self.target_ra[:, np.newaxis],
            self.target_dec[:, np.newaxis],
            self.moon_ra[np.newaxis, :],
            self.moon_dec[np.newaxis, :],
        )
        for row, (ra, dec) in self._tracks.items():
            distance[row] = separation(ra, dec, self.moon_ra, self.moon_dec)
        return distance
