"""Reading the Tycho-2 stars out of an astrometry.net index file (Debian ``astrometry-data-tycho2``).

An index file holds, besides its quads, the stars it was built from: HDU ``kdtree_data_stars``
stores each star as a unit vector of three little-endian u32 (scaled by the tree's
``kdtree_range_stars``: lower bounds, upper bounds, then the scale in tree units per data unit) and
the tag-along table holds ``MAG_VT`` in the same row order. ``index-tycho2-07`` (the finest scale
Debian ships) keeps 1,871,011 of Tycho-2's 2.5 million stars: the brightest ten per 0.14 deg²
healpix cell, so it is complete to VT ~ 12 away from the Milky Way and shallower inside it.

Rendering exactly these stars means ``solve-field`` finds its own quads on every simulated frame,
wherever the telescope points. Positions are Tycho-2's, at epoch J2000 (the index keeps no proper
motions).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]

__all__ = ["TYCHO2_EPOCH_JYEAR", "TYCHO2_INDEX", "Tycho2Stars", "read_tycho2_index"]

FloatArray = npt.NDArray[np.float64]

TYCHO2_INDEX = Path("/usr/share/astrometry/index-tycho2-07.littleendian.fits")
"""The index file read by default: the finest-scale one holds the most stars."""
TYCHO2_EPOCH_JYEAR = 2000.0
"""Epoch of the Tycho-2 positions in the index files."""


@dataclass(frozen=True)
class Tycho2Stars:
    """Stars of one index file, in file order; angles in degrees."""

    ra: FloatArray
    dec: FloatArray
    mag_vt: npt.NDArray[np.float32]


def _hdu_with_column(hdus: fits.HDUList, column: str, path: Path) -> fits.BinTableHDU:
    for hdu in hdus[1:]:
        if column in getattr(hdu, "columns", fits.ColDefs([])).names:
            return hdu
    raise ValueError(f"{path}: no table with column {column!r}; not an astrometry.net index file?")


def read_tycho2_index(path: Path = TYCHO2_INDEX) -> Tycho2Stars:
    """All stars of the astrometry.net index file ``path`` with their Tycho VT magnitudes."""
    if not path.is_file():
        raise FileNotFoundError(f"{path}: Tycho-2 index missing (install astrometry-data-tycho2)")
    with fits.open(path, memmap=True) as hdus:
        if hdus[0].header.get("ENDIAN") != "04:03:02:01":
            raise ValueError(f"{path}: expected a little-endian index file")
        ranges = np.frombuffer(_hdu_with_column(hdus, "kdtree_range_stars", path).data.tobytes(), dtype="<f8")
        raw = _hdu_with_column(hdus, "kdtree_data_stars", path).data.tobytes()
        mag = np.asarray(_hdu_with_column(hdus, "MAG_VT", path).data["MAG_VT"], dtype=np.float32)
    if len(ranges) != 7:
        raise ValueError(f"{path}: kdtree_range_stars has {len(ranges)} values, expected 7")
    xyz = np.frombuffer(raw, dtype="<u4").reshape(-1, 3).astype(np.float64) / ranges[6] + ranges[:3]
    if len(xyz) != len(mag):
        raise ValueError(f"{path}: {len(xyz)} star positions but {len(mag)} magnitudes")
    xyz /= np.linalg.norm(xyz, axis=1, keepdims=True)
    ra = np.mod(np.degrees(np.arctan2(xyz[:, 1], xyz[:, 0])), 360.0)
    dec = np.degrees(np.arcsin(np.clip(xyz[:, 2], -1.0, 1.0)))
    return Tycho2Stars(ra=ra, dec=dec, mag_vt=mag)
