"""astrometry.net index files of the simulated sky, built on demand with ``build-astrometry-index``.

Debian's Tycho-2 index files start at 22' quads and hold no star fainter than VT ~ 12, so they
cannot solve a 20' frame of the simulated sky. A real observatory installs the index series that
fits its field (docs/pipeline.md); the simulated sky has its own, built here from exactly the stars
the renderer draws (real and synthetic, :class:`~nightcrew.sim.catalog.StarCatalog`) with
astrometry.net's own ``build-astrometry-index``. The solvers (``solve-field``, ``nightcrew
solver``, the pipeline's astrometry processors) are then pointed at the directory like at any
other index directory; nothing outside the simulator needs to know how the stars were made.

Files are built per tile and quad scale, only where frames are taken: a tile is one cell of the
catalog's 1 deg grid (:class:`~nightcrew.sim.sky_cells.SkyGrid`) with the stars of a cone that
reaches :data:`TILE_MARGIN_DEG` beyond it, so any field centred in the cell, up to ~1 deg across
with a pointing error of some arcminutes, lies inside one tile. A scale is astrometry.net's preset
number (``-P``: quads of 2'..2.8' times sqrt(2)**scale); a field of width W needs the scales whose
quads span 0.45 W .. 0.6 W (:func:`index_scales_for_field`).

The directory (:func:`sky_index_dir`: ``$NIGHTCREW_CACHE_DIR`` or ``~/.cache/nightcrew``, then
``indexes/seed<seed>-G<depth>``, a name a configuration file can write) holds the files of one
sky; its ``SKY.txt`` names the sky exactly (:func:`sky_id`: seed, depth and a hash of the star
sources' versions and the catalog's model). When that changes (other star sources installed), the
builder removes the old files and builds anew. Files are written beside and renamed, so
concurrent builders and readers never see half a file. Positions are at
the catalog's epoch J2016.0 (like Gaia-based index series).
"""

from __future__ import annotations

import hashlib
import logging
import math
import os
import shutil
import subprocess
import tempfile
import time
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np
from astropy.table import Table  # type: ignore[import-untyped]

from nightcrew.sim.catalog import StarCatalog
from nightcrew.sim.catalog_data import CATALOG_EPOCH_JYEAR
from nightcrew.sim.index_files import index_scales_for_field, scale_quads_arcmin
from nightcrew.sim.real_stars import cache_root, star_sources
from nightcrew.sim.sky_cells import SkyCell

__all__ = [
    "BUILDER_PACKAGE",
    "IndexBuildError",
    "SkyIndexBuilder",
    "index_file_name",
    "sky_id",
    "sky_index_dir",
]

log = logging.getLogger(__name__)

BUILDER_PACKAGE = "astrometry.net"
"""The Debian package with ``build-astrometry-index``."""
TILE_MARGIN_DEG = 0.5
"""How far a tile's stars reach beyond its cell."""
_FORMAT = "1"  # bump when the files' content changes for the same sky
_TAIL = 1500  # characters of the builder's output quoted in an error


class IndexBuildError(RuntimeError):
    """``build-astrometry-index`` is missing or failed (the message says which and why)."""


def sky_id(catalog: StarCatalog) -> str:
    """The name of the simulated sky ``catalog`` draws: seed, depth and a hash of sources and model.

    Raises:
        StarSourceMissingError: a star source is not installed.
    """
    key = hashlib.sha256(_FORMAT.encode())
    key.update(star_sources().encode())
    key.update(f"{catalog.count_growth_per_mag}:{catalog.grid.band_height}:{CATALOG_EPOCH_JYEAR}".encode())
    key.update(f"{TILE_MARGIN_DEG}".encode())
    return f"seed{catalog.seed}-G{catalog.depth:g}-{key.hexdigest()[:10]}"


def sky_index_dir(catalog: StarCatalog, root: Path | None = None) -> Path:
    """Where the index files of ``catalog``'s sky are kept (see the module docstring)."""
    return (root or cache_root()) / "indexes" / f"seed{catalog.seed}-G{catalog.depth:g}"


def index_file_name(scale: int, cell_id: int) -> str:
    """File name of one tile at one scale (``index-*.fits``, as index directories are searched)."""
    return f"index-sim-{scale:02d}-{cell_id:05d}.fits"


def _cell_cone(cell: SkyCell) -> tuple[float, float, float]:
    """Centre (ra, dec) and radius (deg) of a cone that holds ``cell`` plus the tile margin."""
    if cell.dec_max >= 90.0 or cell.dec_min <= -90.0:  # a polar cap: centre it on the pole
        pole = 90.0 if cell.dec_max >= 90.0 else -90.0
        return 0.0, pole, 90.0 - min(abs(cell.dec_min), abs(cell.dec_max)) + TILE_MARGIN_DEG
    ra0, dec0 = 0.5 * (cell.ra_min + cell.ra_max), 0.5 * (cell.dec_min + cell.dec_max)
    # The farthest point of a cell from its centre is on its border: sample the border densely.
    t = np.linspace(0.0, 1.0, 33)
    along_ra = cell.ra_min + t * (cell.ra_max - cell.ra_min)
    along_dec = cell.dec_min + t * (cell.dec_max - cell.dec_min)
    ra = np.concatenate([along_ra, along_ra, np.full(33, cell.ra_min), np.full(33, cell.ra_max)])
    dec = np.concatenate([np.full(33, cell.dec_min), np.full(33, cell.dec_max), along_dec, along_dec])
    r0, d0, r1, d1 = math.radians(ra0), math.radians(dec0), np.radians(ra), np.radians(dec)
    cos_distance = np.sin(d0) * np.sin(d1) + np.cos(d0) * np.cos(d1) * np.cos(r1 - r0)
    radius = float(np.degrees(np.arccos(np.clip(cos_distance, -1.0, 1.0))).max())
    return ra0, dec0, radius + TILE_MARGIN_DEG


class SkyIndexBuilder:
    """Builds the index files of the simulated sky where frames are taken (see the module docstring).

    Args:
        catalog: The sky (the camera's catalog: same seed and depth).
        root: Cache root instead of ``$NIGHTCREW_CACHE_DIR`` / ``~/.cache/nightcrew``.
        executable: ``build-astrometry-index``, looked up on ``PATH`` when a build starts.
        progress: Called with one line per file built (default: logged at INFO).

    Building one tile at one scale takes about a second (a few in the Milky Way); files are kept.
    """

    def __init__(
        self,
        catalog: StarCatalog,
        *,
        root: Path | None = None,
        executable: str = "build-astrometry-index",
        progress: Callable[[str], None] | None = None,
    ) -> None:
        self.catalog = catalog
        self.root = root
        self.executable = executable
        self.progress = progress or (lambda line: log.info("%s", line))

    @property
    def directory(self) -> Path:
        """The index directory of this sky."""
        return sky_index_dir(self.catalog, self.root)

    def _blocking_claim(self, directory: Path) -> None:
        """Make ``directory`` this sky's: files of another sky (other star sources) are removed."""
        stamp = directory / "SKY.txt"
        current = sky_id(self.catalog)
        if stamp.is_file() and stamp.read_text().split("\n", 1)[0] != current:
            self.progress(f"{directory}: built for another sky ({stamp.read_text().split()[0]}); rebuilding")
            for path in directory.glob("index-*.fits"):
                path.unlink()
        directory.mkdir(parents=True, exist_ok=True)
        stamp.write_text(
            f"{current}\nstar sources: {star_sources()}\nseed {self.catalog.seed}, "
            f"synthetic stars to G = {self.catalog.depth:g}, positions at J{CATALOG_EPOCH_JYEAR:g}\n"
        )

    def missing(self, fields: Iterable[tuple[float, float]], scales: Iterable[int]) -> list[tuple[int, int]]:
        """(scale, cell) of the files that fields centred at ``fields`` (ra, dec deg) still lack."""
        directory = self.directory
        cells = sorted(
            {
                int(c)
                for ra, dec in fields
                for c in self.catalog.grid.cell_ids(np.array([ra]), np.array([dec]))
            }
        )
        return [
            (scale, cell)
            for scale in sorted(set(scales))
            for cell in cells
            if not (directory / index_file_name(scale, cell)).is_file()
        ]

    def blocking_build(self, fields: Iterable[tuple[float, float]], *, width_arcmin: Iterable[float]) -> Path:
        """Build what frames of these widths (arcmin) centred at ``fields`` need; the directory.

        Raises:
            IndexBuildError: ``build-astrometry-index`` is missing or fails.
            StarSourceMissingError: a star source of the sky is not installed.
        """
        centres = list(fields)
        scales = {s for width in width_arcmin for s in index_scales_for_field(width)}
        directory = self.directory
        stamp = directory / "SKY.txt"
        fresh = stamp.is_file() and stamp.read_text().split("\n", 1)[0] == sky_id(self.catalog)
        if fresh and not self.missing(centres, scales):
            return directory
        self._blocking_claim(directory)
        todo = self.missing(centres, scales)
        executable = shutil.which(self.executable)
        if executable is None:
            raise IndexBuildError(
                f"{self.executable} not found: the simulated sky's index files are built with it "
                f"(Debian: apt-get install {BUILDER_PACKAGE})"
            )
        for number, (scale, cell) in enumerate(todo, start=1):
            started = time.perf_counter()
            count = self._blocking_build_one(executable, directory, scale, cell)
            low, high = scale_quads_arcmin(scale)
            self.progress(
                f"sky index {number}/{len(todo)}: tile {cell} at quads {low:.3g}'..{high:.3g}' "
                f"({count} stars) in {time.perf_counter() - started:.1f} s"
            )
        return directory

    def _blocking_build_one(self, executable: str, directory: Path, scale: int, cell_id: int) -> int:
        ra, dec, radius = _cell_cone(self.catalog.grid.cell(cell_id))
        stars = self.catalog.query(ra, dec, min(radius, 30.0))
        with tempfile.TemporaryDirectory(prefix=".building-", dir=directory) as workdir:
            work = Path(workdir)
            Table({"RA": stars["ra"], "DEC": stars["dec"], "MAG": stars["mag"]}).write(work / "stars.fits")
            output = work / "index.fits"
            command = [executable, "-i", str(work / "stars.fits"), "-o", str(output), "-P", str(scale)]
            command += ["-E", "-S", "MAG", "-A", "RA", "-D", "DEC", "-t", str(work)]
            command += ["-I", str(7_000_000 + 100_000 * scale + cell_id)]
            result = subprocess.run(
                command, capture_output=True, text=True, stdin=subprocess.DEVNULL, check=False, timeout=600
            )
            if result.returncode != 0 or not output.is_file():
                raise IndexBuildError(
                    f"{' '.join(command)} failed (exit code {result.returncode}):\n"
                    f"{(result.stdout + result.stderr)[-_TAIL:]}"
                )
            os.replace(output, directory / index_file_name(scale, cell_id))
        return len(stars)
