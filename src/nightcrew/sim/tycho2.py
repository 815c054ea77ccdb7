"""The Tycho-2 stars of astrometry.net's index (Debian ``astrometry-data-tycho2``), via :mod:`.index_files`.

``index-tycho2-07`` (the finest scale Debian ships) keeps 1,871,011 of Tycho-2's 2.5 million
stars: the brightest ten per 0.14 deg² healpix cell, so it is complete to VT ~ 12 away from the
Milky Way and shallower inside it. Positions are Tycho-2's, at epoch J2000 (the index keeps no
proper motions); magnitudes are Tycho VT.
"""

from __future__ import annotations

from pathlib import Path

from nightcrew.sim.index_files import IndexStars, read_index_stars

__all__ = ["TYCHO2_EPOCH_JYEAR", "TYCHO2_INDEX", "TYCHO2_PACKAGE", "read_tycho2_index"]

TYCHO2_INDEX = Path("/usr/share/astrometry/index-tycho2-07.littleendian.fits")
"""The index file read by default: the finest-scale one holds the most stars."""
TYCHO2_PACKAGE = "astrometry-data-tycho2"
"""The Debian package that installs :data:`TYCHO2_INDEX`."""
TYCHO2_EPOCH_JYEAR = 2000.0
"""Epoch of the Tycho-2 positions in the index files."""


def read_tycho2_index(path: Path = TYCHO2_INDEX) -> IndexStars:
    """All stars of the Tycho-2 index file ``path`` with their VT magnitudes (``mag``)."""
    if not path.is_file():
        raise FileNotFoundError(f"{path}: Tycho-2 index missing (install {TYCHO2_PACKAGE})")
    return read_index_stars(path)
