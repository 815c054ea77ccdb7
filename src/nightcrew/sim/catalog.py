"""Star catalog for the simulated sky: real stars to G ~ 12 plus deterministic synthetic fainter ones.

Real stars come from :mod:`nightcrew.sim.real_stars`: Gaia DR3 to G = 10 (positions at J2016.0,
Hipparcos proper motions) and the Tycho-2 stars of astrometry.net's index, so ``solve-field`` finds
its quads anywhere on the sky. The index keeps only the brightest stars of crowded fields, so each
sky cell has its own limit of completeness (:func:`cell_mag_limit`); fainter stars down to ``depth``
come from :mod:`nightcrew.sim.synthetic`. Both are cached per sky cell
(:class:`~nightcrew.sim.sky_cells.SkyGrid`) in memory.

Magnitudes are Gaia G for real stars and the same scale for synthetic ones.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from astropy.time import Time  # type: ignore[import-untyped]

from nightcrew.sim.catalog_data import (
    CATALOG_EPOCH_JYEAR,
    CATALOG_MAG_LIMIT,
    ReferenceStars,
    propagate,
    unit_vectors,
)
from nightcrew.sim.real_stars import REAL_MAG_LIMIT, load_real_stars
from nightcrew.sim.sky_cells import SkyGrid
from nightcrew.sim.synthetic import synthetic_stars

__all__ = ["STAR_DTYPE", "StarCatalog", "cell_mag_limit", "epoch_jyear"]

STAR_DTYPE = np.dtype(
    [
        ("ra", "f8"),
        ("dec", "f8"),
        ("mag", "f4"),
        ("source_id", "i8"),
        ("synthetic", "?"),
    ]
)
"""Rows returned by :meth:`StarCatalog.query`: ra/dec in degrees at the requested epoch; source_id is
the Gaia DR3 id, ``-HIP`` for Hipparcos entries, ``-(1e6 + row)`` for Tycho-2 index stars and 0 for
synthetic stars."""

_CELL_DTYPE = np.dtype([*STAR_DTYPE.descr, ("pmra", "f8"), ("pmdec", "f8")])


def cell_mag_limit(real_mags: npt.NDArray[np.float32]) -> float:
    """Magnitude to which a cell's real stars are taken as complete; synthetic stars start there.

    The 90th percentile of the cell's real magnitudes, within [10, 12]: where the solver's index
    kept only the brightest stars (the Milky Way), it lies brighter than 12, and the synthetic
    stars fill in below it instead of leaving a gap. Gaia is complete to 10 everywhere.
    """
    if len(real_mags) == 0:
        return REAL_MAG_LIMIT
    return float(np.clip(np.quantile(real_mags, 0.9), CATALOG_MAG_LIMIT, REAL_MAG_LIMIT))


def epoch_jyear(epoch: Time | float) -> float:
    """Julian year of an epoch given as astropy ``Time`` or as a Julian-year float."""
    if isinstance(epoch, Time):
        return float(epoch.tt.jyear)
    return float(epoch)


class StarCatalog:
    """Cone queries on real + synthetic stars, with proper motion applied to the requested epoch.

    Args:
        depth: faintest magnitude of the synthetic stars (G); at most a cell's real limit
            (10 .. 12) means no synthetic stars there.
        cell_size_deg: size of the cache / synthetic seeding cells.
        count_growth_per_mag: growth of synthetic number counts per magnitude (see synthetic).
        seed: base seed of the synthetic stars; the same seed gives the same sky.
        reference: real stars to use instead of the bundled catalogs (for tests).

    The constructor does no I/O: the real stars are read on the first query (from a cache file in
    well under a second; building that file once takes ~10 s) and kept in memory.
    """

    def __init__(
        self,
        *,
        depth: float = 16.0,
        cell_size_deg: float = 1.0,
        count_growth_per_mag: float = 2.5,
        seed: int = 0,
        reference: ReferenceStars | None = None,
    ) -> None:
        if not CATALOG_MAG_LIMIT - 5.0 <= depth <= 22.0:
            raise ValueError(f"depth must be within [{CATALOG_MAG_LIMIT - 5.0}, 22], got {depth}")
        if count_growth_per_mag <= 1.0:
            raise ValueError(f"count_growth_per_mag must be > 1, got {count_growth_per_mag}")
        self.depth = depth
        self.count_growth_per_mag = count_growth_per_mag
        self.seed = seed
        self.grid = SkyGrid(cell_size_deg)
        self._reference = reference
        self._order: npt.NDArray[np.intp] | None = None
        self._cell_starts: npt.NDArray[np.intp] | None = None
        self._cells: dict[int, npt.NDArray[np.void]] = {}

    def query(
        self,
        ra_deg: float,
        dec_deg: float,
        radius_deg: float,
        *,
        epoch: Time | float = CATALOG_EPOCH_JYEAR,
        mag_limit: float | None = None,
    ) -> npt.NDArray[np.void]:
        """Stars within ``radius_deg`` of (``ra_deg``, ``dec_deg``) at ``epoch``, brighter than ``mag_limit``.

        Returns a structured array of :data:`STAR_DTYPE`, sorted by magnitude (brightest first).
        ``mag_limit`` defaults to the catalog depth. The cone is tested on positions at the
        requested epoch.
        """
        if not 0.0 < radius_deg <= 30.0:
            raise ValueError(f"radius_deg must be within (0, 30], got {radius_deg}")
        if not -90.0 <= dec_deg <= 90.0:
            raise ValueError(f"dec_deg must be within [-90, 90], got {dec_deg}")
        limit = self.depth if mag_limit is None else mag_limit
        years = epoch_jyear(epoch) - CATALOG_EPOCH_JYEAR
        # Fast stars move up to ~10"/yr: widen the cell search so they are not lost at the edge.
        margin = min(1.0, abs(years) * 11.0 / 3600.0)
        cells = [self._cell(c) for c in self.grid.cells_in_cone(ra_deg, dec_deg, radius_deg + margin)]
        stars = np.concatenate(cells) if cells else np.zeros(0, _CELL_DTYPE)
        stars = stars[stars["mag"] < limit]
        ra, dec = stars["ra"], stars["dec"]
        moving = (stars["pmra"] != 0.0) | (stars["pmdec"] != 0.0)
        if years != 0.0 and moving.any():
            ra = ra.copy()
            dec = dec.copy()
            ra[moving], dec[moving] = propagate(
                ra[moving], dec[moving], stars["pmra"][moving], stars["pmdec"][moving], years
            )
        centre = unit_vectors(np.array([ra_deg]), np.array([dec_deg]))[0]
        inside = unit_vectors(ra, dec) @ centre >= np.cos(np.radians(radius_deg))
        out = np.zeros(int(inside.sum()), STAR_DTYPE)
        out["ra"], out["dec"] = ra[inside], dec[inside]
        for name in ("mag", "source_id", "synthetic"):
            out[name] = stars[name][inside]
        return out[np.argsort(out["mag"], kind="stable")]

    def _reference_stars(self) -> ReferenceStars:
        if self._reference is None:
            self._reference = load_real_stars()
        return self._reference

    def _cell(self, cell_id: int) -> npt.NDArray[np.void]:
        cached = self._cells.get(cell_id)
        if cached is not None:
            return cached
        ref = self._reference_stars()
        if self._order is None or self._cell_starts is None:
            ids = self.grid.cell_ids(ref.ra, ref.dec)
            self._order = np.argsort(ids, kind="stable")
            self._cell_starts = np.searchsorted(ids[self._order], np.arange(self.grid.n_cells + 1))
        rows = self._order[self._cell_starts[cell_id] : self._cell_starts[cell_id + 1]]
        cell = self.grid.cell(cell_id)
        limit = cell_mag_limit(ref.mag[rows])
        # The density at the limit is scaled from the last magnitude above Gaia's G = 10, which is
        # complete everywhere (the index's own counts are cut in crowded cells).
        mags = ref.mag[rows]
        gaia_last_mag = np.count_nonzero((mags >= CATALOG_MAG_LIMIT - 1.0) & (mags < CATALOG_MAG_LIMIT))
        fake_ra, fake_dec, fake_mag = synthetic_stars(
            cell,
            real_count_last_mag=round(
                gaia_last_mag * self.count_growth_per_mag ** (limit - CATALOG_MAG_LIMIT)
            ),
            mag_limit=limit,
            depth=self.depth,
            count_growth_per_mag=self.count_growth_per_mag,
            seed=self.seed,
        )
        stars = np.zeros(len(rows) + len(fake_mag), _CELL_DTYPE)
        n = len(rows)
        stars["ra"][:n], stars["dec"][:n], stars["mag"][:n] = ref.ra[rows], ref.dec[rows], ref.mag[rows]
        stars["source_id"][:n] = ref.source_id[rows]
        stars["pmra"][:n], stars["pmdec"][:n] = ref.pmra[rows], ref.pmdec[rows]
        stars["ra"][n:], stars["dec"][n:], stars["mag"][n:] = fake_ra, fake_dec, fake_mag
        stars["synthetic"][n:] = True
        self._cells[cell_id] = stars
        return stars
