"""Reading the stars out of an astrometry.net index file (any series: Debian's Tycho-2, the simulated sky's).

An index file holds, besides its quads, the stars it was built from: HDU ``kdtree_data_stars``
stores each star as a unit vector of three little-endian u32 (scaled by the tree's
``kdtree_range_stars``: lower bounds, upper bounds, then the scale in tree units per data unit) and
the tag-along table holds a magnitude column (``MAG_VT`` in Debian's Tycho-2 files, ``MAG`` in the
files :mod:`nightcrew.sim.sky_index` builds) in the same row order. The primary header gives the
quad scales (``SCALE_L``, ``SCALE_U``, radians).

A scale is astrometry.net's preset number (``build-astrometry-index -P``, the last two digits of
the 4100/4200/5200 series' file names): quads of 2'..2.8' times sqrt(2)**scale. A field of width W
is solved with the scales whose quads span 0.45 W .. 0.6 W (:func:`index_scales_for_field`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]

__all__ = [
    "QUAD_FRACTIONS",
    "IndexStars",
    "index_quad_scale_arcsec",
    "index_scales_for_field",
    "read_index_stars",
    "scale_quads_arcmin",
]

FloatArray = npt.NDArray[np.float64]

QUAD_FRACTIONS = (0.45, 0.6)
"""Quads from this fraction to that of a field's width solve it (smaller ones: too few stars)."""
MAG_COLUMNS = ("MAG", "MAG_VT", "mag")
"""Tag-along columns taken as the stars' magnitudes, first found wins."""


@dataclass(frozen=True)
class IndexStars:
    """Stars of one index file, in file order; angles in degrees, magnitudes as the file has them."""

    ra: FloatArray
    dec: FloatArray
    mag: npt.NDArray[np.float32]


def scale_quads_arcmin(scale: int) -> tuple[float, float]:
    """Smallest and largest quad diameter (arcmin) of astrometry.net's preset ``scale`` (``-P``)."""
    factor = math.sqrt(2.0) ** scale
    return 2.0 * factor, 2.8 * factor


def index_scales_for_field(width_arcmin: float) -> list[int]:
    """The preset scales whose quads fit a field ``width_arcmin`` wide (quads of 0.45 .. 0.6 of it)."""
    if not width_arcmin > 0:
        raise ValueError(f"width_arcmin must be positive, got {width_arcmin}")
    low, high = (fraction * width_arcmin for fraction in QUAD_FRACTIONS)
    scales = [s for s in range(20) if scale_quads_arcmin(s)[1] > low and scale_quads_arcmin(s)[0] < high]
    if not scales:
        raise ValueError(f"no astrometry.net scale fits a field of {width_arcmin:g}'")
    return scales


def _hdu_with_column(
    hdus: fits.HDUList, columns: tuple[str, ...], path: Path
) -> tuple[fits.BinTableHDU, str]:
    for hdu in hdus[1:]:
        names = getattr(hdu, "columns", fits.ColDefs([])).names
        for column in columns:
            if column in names:
                return hdu, column
    raise ValueError(
        f"{path}: no table with column {' or '.join(columns)}; not an astrometry.net index file?"
    )


def index_quad_scale_arcsec(path: Path) -> tuple[float, float] | None:
    """Smallest and largest quad diameter (arcsec) of the index file ``path``; None when not stated."""
    header = fits.getheader(path)
    low, high = header.get("SCALE_L"), header.get("SCALE_U")  # radians
    if isinstance(low, float) and isinstance(high, float):
        return math.degrees(low) * 3600.0, math.degrees(high) * 3600.0
    return None


def read_index_stars(path: Path) -> IndexStars:
    """All stars of the astrometry.net index file ``path`` with their magnitudes.

    Raises:
        FileNotFoundError: ``path`` does not exist.
        ValueError: it is not a little-endian index file with a magnitude column.
    """
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such index file")
    with fits.open(path, memmap=True) as hdus:
        if hdus[0].header.get("ENDIAN") != "04:03:02:01":
            raise ValueError(f"{path}: expected a little-endian index file")
        ranges_hdu, _ = _hdu_with_column(hdus, ("kdtree_range_stars",), path)
        ranges = np.frombuffer(ranges_hdu.data.tobytes(), dtype="<f8")
        raw = _hdu_with_column(hdus, ("kdtree_data_stars",), path)[0].data.tobytes()
        mag_hdu, mag_column = _hdu_with_column(hdus, MAG_COLUMNS, path)
        mag = np.asarray(mag_hdu.data[mag_column], dtype=np.float32)
    if len(ranges) != 7:
        raise ValueError(f"{path}: kdtree_range_stars has {len(ranges)} values, expected 7")
    xyz = np.frombuffer(raw, dtype="<u4").reshape(-1, 3).astype(np.float64) / ranges[6] + ranges[:3]
    if len(xyz) != len(mag):
        raise ValueError(f"{path}: {len(xyz)} star positions but {len(mag)} magnitudes")
    xyz /= np.linalg.norm(xyz, axis=1, keepdims=True)
    ra = np.mod(np.degrees(np.arctan2(xyz[:, 1], xyz[:, 0])), 360.0)
    dec = np.degrees(np.arcsin(np.clip(xyz[:, 2], -1.0, 1.0)))
    return IndexStars(ra=ra, dec=dec, mag=mag)
