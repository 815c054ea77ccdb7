"""Deterministic synthetic stars fainter than the real catalog, one reproducible set per sky cell.

Number-count model: the differential density of stars per magnitude grows geometrically,
``dN/dm = A * g**(m - m_lim)`` with ``g`` (``count_growth_per_mag``, default 2.5) the growth per
magnitude; real counts grow by ~x2.5-3 per mag around m = 10-17, flattening slowly. ``A`` (stars
per mag at the catalog limit in the cell) is taken from the cell's own real stars in the last
magnitude above the limit, ``C1 = A * (1 - 1/g) / ln g``, so the Milky Way stays denser than the
galactic poles. The number of synthetic stars in ``[m_lim, depth]`` is Poisson with mean
``A * (g**D - 1) / ln g`` (``D = depth - m_lim``); magnitudes follow by inverse transform
sampling and positions are uniform on the sphere inside the cell. The generator is seeded with
``(seed, band, index)`` of the cell, so the same cell always holds the same stars.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from nightcrew.sim.sky_cells import SkyCell

__all__ = ["synthetic_stars"]

FloatArray = npt.NDArray[np.float64]


def synthetic_stars(
    cell: SkyCell,
    *,
    real_count_last_mag: int,
    mag_limit: float,
    depth: float,
    count_growth_per_mag: float = 2.5,
    seed: int = 0,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Positions (deg) and magnitudes of the synthetic stars of ``cell`` between ``mag_limit`` and ``depth``.

    ``real_count_last_mag`` is the number of real catalog stars of the cell with magnitude in
    ``[mag_limit - 1, mag_limit)``; one is added to it so that empty cells still get faint stars.
    """
    g = count_growth_per_mag
    if g <= 1.0:
        raise ValueError(f"count_growth_per_mag must be > 1, got {g}")
    rng = np.random.default_rng([seed, cell.band, cell.index])
    span = depth - mag_limit
    if span <= 0:
        empty = np.zeros(0)
        return empty, empty.copy(), empty.copy()
    log_g = math.log(g)
    density_at_limit = (real_count_last_mag + 1) * log_g / (1.0 - 1.0 / g)
    mean_count = density_at_limit * (g**span - 1.0) / log_g
    n = int(rng.poisson(mean_count))
    u = rng.random(n)
    mag = mag_limit + np.log1p(u * (g**span - 1.0)) / log_g
    ra = cell.ra_min + rng.random(n) * (cell.ra_max - cell.ra_min)
    sin_lo = math.sin(math.radians(cell.dec_min))
    sin_hi = math.sin(math.radians(cell.dec_max))
    dec = np.degrees(np.arcsin(sin_lo + rng.random(n) * (sin_hi - sin_lo)))
    return ra, dec, mag
