"""The stars of a directory of astrometry.net index files, as a reference catalog for the matcher.

An observatory that solves with astrometry.net has its index files anyway, and each file keeps the
stars its quads were built from (read by :func:`~nightcrew.sim.index_files.read_index_stars`). So
the fast :class:`~nightcrew.images.astrometry.CatalogMatcher` takes its reference stars from the
same directory ``solve-field`` and ``nightcrew solver`` use: no second catalog to install, and
whatever sky the indexes describe (Debian's Tycho-2, a 5200 series, the simulated sky's) is the
sky the matcher sees.

A query uses a file of the finest quad scale that covers the position (those keep the most stars),
of several the one the position lies deepest inside; a file covers the cap around the mean
direction of its stars out to its farthest star. Files are read
once, when a query first needs them, and kept in memory; files added to the directory later are
found on the next query.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from nightcrew.images.astrometry._errors import NoSolutionError, SolverUnavailableError
from nightcrew.sim.catalog_data import unit_vectors
from nightcrew.sim.index_files import IndexStars, index_quad_scale_arcsec, read_index_stars

__all__ = ["IndexCatalog"]

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class _LoadedIndex:
    stars: IndexStars
    xyz: FloatArray
    centre: FloatArray
    cos_radius: float


class IndexCatalog:
    """Cone queries on the stars of the index files (``index-*.fits``) in ``directory``.

    The constructor does no I/O; :meth:`query` is thread-safe.
    """

    def __init__(self, directory: str | Path) -> None:
        self.directory = Path(directory).expanduser()
        self._files: list[list[Path]] | None = None
        self._listed = 0
        self._loaded: dict[Path, _LoadedIndex] = {}
        self._lock = threading.Lock()

    def _index_files(self) -> list[list[Path]]:
        """The directory's index files grouped by smallest quad size, finest first."""
        try:
            listed = self.directory.stat().st_mtime_ns
        except OSError:
            raise SolverUnavailableError(f"index directory {self.directory} does not exist") from None
        if self._files is None or listed != self._listed:  # files added since: look again
            self._listed = listed
            groups: dict[float, list[Path]] = {}
            for path in sorted(self.directory.glob("index-*.fits")):
                scale = index_quad_scale_arcsec(path)
                if scale is not None:
                    groups.setdefault(round(scale[0], 1), []).append(path)
            if not groups:
                raise SolverUnavailableError(
                    f"no astrometry.net index files (index-*.fits) in {self.directory}"
                )
            self._files = [groups[key] for key in sorted(groups)]
        return self._files

    def _load(self, path: Path) -> _LoadedIndex:
        loaded = self._loaded.get(path)
        if loaded is None:
            stars = read_index_stars(path)
            xyz = unit_vectors(stars.ra, stars.dec)
            centre = xyz.sum(axis=0)
            norm = float(np.linalg.norm(centre))
            # An all-sky file (or one around a pole) has no useful centre: it covers everything.
            centre = centre / norm if norm > 1e-6 * len(xyz) else np.array([0.0, 0.0, 1.0])
            cos_radius = float((xyz @ centre).min()) if norm > 1e-6 * len(xyz) else -1.0
            loaded = self._loaded[path] = _LoadedIndex(stars, xyz, centre, cos_radius)
        return loaded

    def query(
        self, ra_deg: float, dec_deg: float, radius_deg: float
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """RA, Dec (deg) and magnitude of the stars within ``radius_deg``, brightest first.

        Raises:
            SolverUnavailableError: the directory holds no index files.
            NoSolutionError: none of them covers the position.
        """
        probe = unit_vectors(np.array([ra_deg]), np.array([dec_deg]))[0]
        with self._lock:
            for group in self._index_files():
                depths = {path: _depth_inside(self._load(path), probe) for path in group}
                path = max(depths, key=lambda p: depths[p])
                if depths[path] < 0.0:
                    continue
                index = self._load(path)
                inside = index.xyz @ probe >= np.cos(np.radians(radius_deg))
                order = np.argsort(index.stars.mag[inside], kind="stable")
                return (
                    index.stars.ra[inside][order],
                    index.stars.dec[inside][order],
                    np.asarray(index.stars.mag[inside][order], dtype=np.float64),
                )
        raise NoSolutionError(f"no index file in {self.directory} covers RA {ra_deg:.4f}, Dec {dec_deg:.4f}")


def _depth_inside(index: _LoadedIndex, probe: FloatArray) -> float:
    """How far (radians) ``probe`` lies inside the file's cap; negative outside it."""
    return float(
        np.arccos(np.clip(index.cos_radius, -1.0, 1.0)) - np.arccos(np.clip(index.centre @ probe, -1.0, 1.0))
    )
