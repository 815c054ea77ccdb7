"""Observing constraints as composable callables over the time grid.

A constraint takes a :class:`~nightcrew.robotic.scheduler.sky.SkyGrid` and returns a boolean array
of shape (n_blocks, n_slices): True where the block may be observed during that slice. Each
constraint reads its limit from the block's own :class:`Constraints`, so one list serves all
blocks; :func:`visibility` ANDs a list of them. Add a new kind of condition by writing one more
callable (e.g. a horizon mask), not by changing the solver.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from datetime import datetime
from functools import cache
from typing import Protocol

import numpy as np
import numpy.typing as npt

from nightcrew.astro import airmass
from nightcrew.robotic.scheduler.sky import SkyGrid

__all__ = [
    "DEFAULT_CONSTRAINTS",
    "AirmassConstraint",
    "Constraint",
    "MoonDistanceConstraint",
    "MoonIlluminationConstraint",
    "SunAltitudeConstraint",
    "WindowConstraint",
    "startable",
    "visibility",
]

BoolArray = npt.NDArray[np.bool_]


class Constraint(Protocol):
    """Where on the grid each block may be observed."""

    def __call__(self, sky: SkyGrid) -> BoolArray:
        """Boolean array (n_blocks, n_slices)."""
        ...


def _on_both_edges(ok_at_edges: BoolArray) -> BoolArray:
    """A slice is fine when the condition holds at its start and its end."""
    return np.asarray(ok_at_edges[:, :-1] & ok_at_edges[:, 1:], dtype=np.bool_)


@cache
def altitude_for_airmass(max_airmass: float) -> float:
    """Lowest altitude (degrees) whose airmass (Kasten & Young, as in ``coords``) is <= max_airmass."""
    low, high = 0.0, 90.0  # airmass falls monotonically with altitude
    for _ in range(60):
        middle = (low + high) / 2
        value = airmass(middle)
        if value is not None and value <= max_airmass:
            high = middle
        else:
            low = middle
    return high


class AirmassConstraint:
    """Airmass at most the block's ``max_airmass`` (so also above the horizon); an infinite limit
    (blocks whose target is a stand-in, e.g. calibrations) holds everywhere, below the horizon too."""

    def __call__(self, sky: SkyGrid) -> BoolArray:
        limits = [b.constraints.max_airmass for b in sky.blocks]
        min_alt = np.array([altitude_for_airmass(a) if math.isfinite(a) else -90.0 for a in limits])
        return _on_both_edges(sky.altitude >= min_alt.reshape(-1, 1))


class SunAltitudeConstraint:
    """The Sun at most at the block's ``max_sun_altitude``."""

    def __call__(self, sky: SkyGrid) -> BoolArray:
        limit = np.array([b.constraints.max_sun_altitude for b in sky.blocks]).reshape(-1, 1)
        return _on_both_edges(sky.sun_altitude[np.newaxis, :] <= limit)


class MoonDistanceConstraint:
    """The target at least ``min_moon_distance`` degrees from the Moon."""

    def __call__(self, sky: SkyGrid) -> BoolArray:
        limit = np.array([b.constraints.min_moon_distance for b in sky.blocks]).reshape(-1, 1)
        if not np.any(limit > 0):  # the common case; skip the separations
            return np.ones((len(sky.blocks), sky.grid.n_slices), dtype=np.bool_)
        return _on_both_edges(sky.moon_distance() >= limit)


class MoonIlluminationConstraint:
    """The Moon's illuminated fraction at most ``max_moon_illumination`` (whether it is up or not)."""

    def __call__(self, sky: SkyGrid) -> BoolArray:
        limit = np.array([b.constraints.max_moon_illumination for b in sky.blocks]).reshape(-1, 1)
        return _on_both_edges(sky.moon_illumination[np.newaxis, :] <= limit)


class WindowConstraint:
    """Every slice wholly inside one of the block's observation windows (none: always)."""

    def __call__(self, sky: SkyGrid) -> BoolArray:
        edges = sky.edges
        result = np.ones((len(sky.blocks), sky.grid.n_slices), dtype=np.bool_)
        for row, block in enumerate(sky.blocks):
            if not block.windows:
                continue
            inside = np.zeros(sky.grid.n_slices, dtype=np.bool_)
            for start, end in block.windows:
                inside |= (edges[:-1] >= _unix(start)) & (edges[1:] <= _unix(end))
            result[row] = inside
        return result


def _unix(value: datetime) -> float:
    return value.timestamp()


#: What a block's :class:`Constraints` and windows ask for.
DEFAULT_CONSTRAINTS: tuple[Constraint, ...] = (
    WindowConstraint(),
    SunAltitudeConstraint(),
    AirmassConstraint(),
    MoonIlluminationConstraint(),
    MoonDistanceConstraint(),
)


def visibility(sky: SkyGrid, constraints: Sequence[Constraint] = DEFAULT_CONSTRAINTS) -> BoolArray:
    """Slices where every constraint holds, shape (n_blocks, n_slices)."""
    result = np.ones((len(sky.blocks), sky.grid.n_slices), dtype=np.bool_)
    for constraint in constraints:
        result &= constraint(sky)
    return result


def startable(visible: BoolArray, lengths: npt.NDArray[np.int64]) -> BoolArray:
    """Where each block can start so that all of the slices it occupies are visible.

    Args:
        visible: Visibility (n_blocks, n_slices).
        lengths: Slices each block occupies: one number per block (n_blocks,), or one per block
            and start slice (n_blocks, n_slices); 0 never fits.
    """
    n_blocks, n_slices = visible.shape
    if n_blocks == 0:  # nothing to plan (an empty archive): reshape(0, -1) has no meaning
        return np.zeros((0, n_slices), dtype=np.bool_)
    # visible_count[b, t] = visible slices before t; a start t fits when the next length slices all are.
    visible_count = np.zeros((n_blocks, n_slices + 1), dtype=np.int64)
    np.cumsum(visible, axis=1, out=visible_count[:, 1:])
    starts = np.arange(n_slices)[np.newaxis, :]
    spans = np.broadcast_to(lengths.reshape(n_blocks, -1), (n_blocks, n_slices))
    ends = starts + spans
    fits = (ends <= n_slices) & (spans >= 1)
    clipped = np.minimum(ends, n_slices)
    rows = np.arange(n_blocks)[:, np.newaxis]
    full = visible_count[rows, clipped] - visible_count[rows, starts] == spans
    return np.asarray(fits & full, dtype=np.bool_)
