"""The result of every offsets processor, stored in ``image.metadata["offsets"]``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from nightcrew.images.image import Image

__all__ = ["OFFSETS_KEY", "Offsets", "with_offsets"]

OFFSETS_KEY = "offsets"


@dataclass(frozen=True)
class Offsets:
    """How far the field has moved on the detector, and what that means on the sky.

    Attributes
    ----------
    dx, dy
        Pixel offset of the stars: where they are minus where they should be (the reference, or
        the requested position), 0-based pixels along x (columns) and y (rows).
    d_ra_arcsec, d_dec_arcsec
        The pointing error on the sky (arcsec): where the telescope points minus where it should,
        in RA (times cos Dec) and Dec; apply the negative to correct. None without a WCS.
    source
        The processor's class name.
    is_reference
        True if this image became the new reference (offsets are then zero).
    """

    dx: float
    dy: float
    d_ra_arcsec: float | None = None
    d_dec_arcsec: float | None = None
    source: str = ""
    is_reference: bool = False

    @property
    def distance_px(self) -> float:
        """Length of the pixel offset."""
        return math.hypot(self.dx, self.dy)


def with_offsets(image: Image, dx: float, dy: float, source: str, *, is_reference: bool = False) -> Image:
    """A copy of ``image`` with :class:`Offsets` in its metadata, sky offsets from its WCS if any.

    The sky offset is measured at the image centre: after the pointing error, the centre shows
    the sky that was at ``centre - (dx, dy)``.
    """
    d_ra: float | None = None
    d_dec: float | None = None
    wcs: Any = image.wcs
    if wcs is not None:
        rows, cols = image.shape
        cx, cy = (cols - 1) / 2.0, (rows - 1) / 2.0
        (ra0, ra1), (dec0, dec1) = wcs.all_pix2world([cx, cx - dx], [cy, cy - dy], 0)
        d_ra = (
            ((float(ra1) - float(ra0) + 180.0) % 360.0 - 180.0) * math.cos(math.radians(float(dec0))) * 3600.0
        )
        d_dec = (float(dec1) - float(dec0)) * 3600.0
    result = image.copy()
    result.metadata[OFFSETS_KEY] = Offsets(
        float(dx), float(dy), d_ra, d_dec, source=source, is_reference=is_reference
    )
    return result
