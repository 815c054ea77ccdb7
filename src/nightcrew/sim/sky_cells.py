"""An equal-area-ish grid of sky cells, used to cache catalog stars and seed synthetic ones.

The sky is cut into declination bands of ``cell_size_deg`` height; band ``j`` is cut into
``n_j = max(1, round(360 * cos(dec_mid) / cell_size_deg))`` right-ascension cells, so every cell
covers roughly ``cell_size_deg**2`` square degrees. A cell is identified by ``(band, index)``, which
is stable across processes and so can seed a random generator.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = ["SkyCell", "SkyGrid"]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


@dataclass(frozen=True)
class SkyCell:
    """One cell: declination band ``band`` and right-ascension index ``index`` inside it."""

    band: int
    index: int
    ra_min: float
    ra_max: float
    dec_min: float
    dec_max: float

    @property
    def area_deg2(self) -> float:
        """Solid angle of the cell in square degrees."""
        d_sin = math.sin(math.radians(self.dec_max)) - math.sin(math.radians(self.dec_min))
        return math.degrees(1.0) * (self.ra_max - self.ra_min) * d_sin


class SkyGrid:
    """The cell grid for a given cell size (degrees)."""

    def __init__(self, cell_size_deg: float = 1.0) -> None:
        if not 0.05 <= cell_size_deg <= 30.0:
            raise ValueError(f"cell_size_deg must be within [0.05, 30], got {cell_size_deg}")
        self.n_bands = math.ceil(180.0 / cell_size_deg)
        self.band_height = 180.0 / self.n_bands
        mids = -90.0 + (np.arange(self.n_bands) + 0.5) * self.band_height
        counts = np.maximum(1, np.round(360.0 * np.cos(np.radians(mids)) / self.band_height))
        self.cells_in_band: IntArray = counts.astype(np.int64)
        self._band_offset: IntArray = np.concatenate([[0], np.cumsum(self.cells_in_band)[:-1]])
        self.n_cells = int(self.cells_in_band.sum())

    def cell_ids(self, ra_deg: FloatArray, dec_deg: FloatArray) -> IntArray:
        """Flat cell number (0 .. n_cells-1) of each position."""
        band = np.clip(((dec_deg + 90.0) / self.band_height).astype(np.int64), 0, self.n_bands - 1)
        n = self.cells_in_band[band]
        index = np.minimum((np.mod(ra_deg, 360.0) / 360.0 * n).astype(np.int64), n - 1)
        return np.asarray(self._band_offset[band] + index, dtype=np.int64)

    def cell(self, cell_id: int) -> SkyCell:
        """The cell with flat number ``cell_id``."""
        band = int(np.searchsorted(self._band_offset, cell_id, side="right") - 1)
        index = cell_id - int(self._band_offset[band])
        width = 360.0 / int(self.cells_in_band[band])
        dec_min = -90.0 + band * self.band_height
        return SkyCell(
            band=band,
            index=index,
            ra_min=index * width,
            ra_max=(index + 1) * width,
            dec_min=dec_min,
            dec_max=dec_min + self.band_height,
        )

    def cells_in_cone(self, ra_deg: float, dec_deg: float, radius_deg: float) -> list[int]:
        """Flat numbers of all cells that may overlap the cone (a superset, never a subset)."""
        dec_lo = max(-90.0, dec_deg - radius_deg)
        dec_hi = min(90.0, dec_deg + radius_deg)
        band_lo = max(0, int((dec_lo + 90.0) / self.band_height))
        band_hi = min(self.n_bands - 1, int((dec_hi + 90.0) / self.band_height))
        # A small circle of radius r around dec0 spans RA half-width asin(sin r / cos dec0) when it
        # does not contain a pole; otherwise it spans all right ascensions.
        contains_pole = dec_deg + radius_deg >= 90.0 or dec_deg - radius_deg <= -90.0
        half_width = 180.0
        if not contains_pole:
            ratio = math.sin(math.radians(radius_deg)) / math.cos(math.radians(dec_deg))
            half_width = math.degrees(math.asin(min(1.0, ratio)))
        ids: list[int] = []
        for band in range(band_lo, band_hi + 1):
            n = int(self.cells_in_band[band])
            offset = int(self._band_offset[band])
            if half_width >= 90.0:
                ids.extend(range(offset, offset + n))
                continue
            width = 360.0 / n
            first = math.floor((ra_deg - half_width) / width)
            last = math.floor((ra_deg + half_width) / width)
            ids.extend(sorted({offset + (k % n) for k in range(first, last + 1)}))
        return ids
