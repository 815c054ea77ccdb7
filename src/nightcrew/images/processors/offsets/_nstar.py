"""NStarOffsets: boxes around the N brightest reference stars cross-correlated with the same boxes now."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
from astropy.table import Table  # type: ignore[import-untyped]

from nightcrew.images.errors import NoStarsError
from nightcrew.images.image import Image
from nightcrew.images.processor import require
from nightcrew.images.processors._shared import float_data, saturation_level
from nightcrew.images.processors.detection import detect_sources_sep
from nightcrew.images.processors.offsets._reference import DEFAULT_RESET_KEYWORDS, ReferenceOffsets
from nightcrew.images.processors.offsets._shift import integer_shift, refine_shift

__all__ = ["NStarOffsets", "brightest_stars", "cutouts", "nstar_offsets"]

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


def brightest_stars(
    catalog: Table, shape: tuple[int, int], count: int, edge: int
) -> tuple[IntArray, IntArray]:
    """Whole-pixel centres of the ``count`` brightest unflagged sources at least ``edge`` px inside.

    Raises
    ------
    NoStarsError
        No source qualifies.
    """
    x, y = np.asarray(catalog["x"], np.float64), np.asarray(catalog["y"], np.float64)
    rows, cols = shape
    usable = (np.asarray(catalog["flags"]) == 0) & np.isfinite(x) & np.isfinite(y)
    usable &= (x >= edge) & (x <= cols - 1 - edge) & (y >= edge) & (y <= rows - 1 - edge)
    if not usable.any():
        raise NoStarsError(f"no unsaturated, unblended star at least {edge} px from the edges")
    order = np.argsort(-np.asarray(catalog["peak"], np.float64)[usable], kind="stable")[:count]
    return np.rint(x[usable][order]).astype(np.int64), np.rint(y[usable][order]).astype(np.int64)


def cutouts(data: FloatArray, x: IntArray, y: IntArray, half: int) -> FloatArray:
    """Boxes of ``2 half + 1`` pixels centred on (x, y), each minus its median (the local sky)."""
    boxes = np.stack(
        [data[cy - half : cy + half + 1, cx - half : cx + half + 1] for cx, cy in zip(x, y, strict=True)]
    )
    return np.asarray(boxes - np.median(boxes, axis=(1, 2), keepdims=True), np.float64)


def nstar_offsets(
    reference: FloatArray,
    current: FloatArray,
    x: IntArray,
    y: IntArray,
    *,
    max_shift: int,
    star_half_size: int,
) -> tuple[float, float]:
    """Offsets (dx, dy) in pixels of ``current`` against ``reference`` around stars at (x, y).

    The whole-pixel shift maximises the summed cross-correlation of boxes reaching ``max_shift +
    star_half_size`` around each star; then small boxes (``star_half_size``) around each star,
    moved by that shift in the current frame, are matched to a fraction of a pixel.
    ``(x, y)`` must lie at least ``max_shift + star_half_size + 3`` pixels inside the frame.
    """
    half = max_shift + star_half_size
    shift_y, shift_x = integer_shift(cutouts(reference, x, y, half), cutouts(current, x, y, half), max_shift)
    pad = 3  # refine_shift's margin: the compared boxes stay star_half_size wide
    ref_boxes = cutouts(reference, x, y, star_half_size + pad)
    cur_boxes = cutouts(current, x + shift_x, y + shift_y, star_half_size + pad)
    fine_y, fine_x = refine_shift(ref_boxes, cur_boxes, margin=pad)
    return shift_x + float(fine_x), shift_y + float(fine_y)


@dataclass(frozen=True)
class _Reference:
    data: FloatArray
    x: IntArray
    y: IntArray


class NStarOffsets(ReferenceOffsets[_Reference]):
    """Offsets from boxes around the N brightest stars of the reference.

    The reference's stars come from its catalog if it has one (e.g. from a detection step before
    this one), else from SEP detection here.

    Parameters
    ----------
    stars
        Number of stars used (the brightest unflagged ones).
    max_shift
        Largest offset searched (pixels); stars closer to the edge than this plus
        ``star_half_size`` are not used.
    star_half_size
        Half size (pixels) of the box around a star; about 3 FWHM.
    detection_threshold
        Threshold (sigma, see :func:`~..detection.detect_sources_sep`) when detecting here:
        only bright stars are needed.
    reset_keywords
        Header keywords whose change starts a new reference.
    """

    def __init__(
        self,
        *,
        stars: int = 10,
        max_shift: int = 30,
        star_half_size: int = 10,
        detection_threshold: float = 20.0,
        reset_keywords: Sequence[str] = DEFAULT_RESET_KEYWORDS,
        **kwargs: Any,
    ) -> None:
        super().__init__(reset_keywords=reset_keywords, **kwargs)
        require(stars >= 1, "stars", f"must be >= 1, got {stars}")
        require(max_shift >= 1, "max_shift", f"must be >= 1, got {max_shift}")
        require(star_half_size >= 3, "star_half_size", f"must be >= 3, got {star_half_size}")
        require(detection_threshold > 0, "detection_threshold", f"must be > 0, got {detection_threshold}")
        self.stars = stars
        self.max_shift = max_shift
        self.star_half_size = star_half_size
        self.detection_threshold = detection_threshold

    def _blocking_reference(self, image: Image) -> _Reference:
        data = float_data(image)
        catalog = image.catalog
        if catalog is None:
            catalog = detect_sources_sep(
                float_data(image),
                image.mask,
                threshold=self.detection_threshold,
                saturation=saturation_level(image, None),
            )
        edge = self.max_shift + self.star_half_size + 3
        x, y = brightest_stars(catalog, image.shape, self.stars, edge)
        return _Reference(data, x, y)

    def _blocking_offsets(self, reference: _Reference, image: Image) -> tuple[float, float]:
        return nstar_offsets(
            reference.data,
            np.asarray(image.data, np.float64),
            reference.x,
            reference.y,
            max_shift=self.max_shift,
            star_half_size=self.star_half_size,
        )
