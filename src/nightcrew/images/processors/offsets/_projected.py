"""ProjectedOffsets: the frame summed along rows and columns, each profile matched to the reference's."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy import ndimage  # type: ignore[import-untyped]

from nightcrew.images.errors import NoStarsError
from nightcrew.images.image import Image
from nightcrew.images.processor import require
from nightcrew.images.processors.offsets._reference import DEFAULT_RESET_KEYWORDS, ReferenceOffsets
from nightcrew.images.processors.offsets._shift import integer_shift, refine_shift

__all__ = ["ProjectedOffsets", "projected_offsets"]

FloatArray = npt.NDArray[np.float64]


def _profile(data: FloatArray, axis: int, trend_width: int) -> FloatArray:
    """Sum along ``axis`` minus its running median: sky and vignetting gone, stars left as peaks."""
    summed = data.sum(axis=axis, dtype=np.float64)
    return np.asarray(summed - ndimage.median_filter(summed, size=trend_width, mode="nearest"), np.float64)


def _common(size: int, shift: int) -> tuple[slice, slice]:
    """Ranges of the reference and the current frame that see the same sky for an integer shift."""
    if shift >= 0:
        return slice(0, size - shift), slice(shift, size)
    return slice(-shift, size), slice(0, size + shift)


def projected_offsets(
    reference: FloatArray, current: FloatArray, *, max_shift: int = 50, trend_width: int = 31
) -> tuple[float, float]:
    """Offsets (dx, dy) in pixels of ``current`` against ``reference`` (raw frames of equal shape).

    First both profiles of the whole frames give the whole-pixel shift; then the profiles are
    rebuilt over the part of the sky both frames share (stars that left or entered the frame
    would otherwise change the other axis' profile) and matched to a fraction of a pixel.

    Raises
    ------
    NoStarsError
        The profiles hold no signal to match (a blank frame).
    """
    rows, cols = reference.shape
    ref_x, cur_x = _profile(reference, 0, trend_width), _profile(current, 0, trend_width)
    ref_y, cur_y = _profile(reference, 1, trend_width), _profile(current, 1, trend_width)
    if not (np.any(ref_x) and np.any(ref_y)):
        raise NoStarsError("the reference frame holds no structure to match")
    (shift_x,) = integer_shift(ref_x[None], cur_x[None], max_shift)
    (shift_y,) = integer_shift(ref_y[None], cur_y[None], max_shift)
    ref_cols, cur_cols = _common(cols, shift_x)
    ref_rows, cur_rows = _common(rows, shift_y)
    ref_part, cur_part = reference[ref_rows, ref_cols], current[cur_rows, cur_cols]
    (fine_x,) = refine_shift(
        _profile(ref_part, 0, trend_width)[None], _profile(cur_part, 0, trend_width)[None]
    )
    (fine_y,) = refine_shift(
        _profile(ref_part, 1, trend_width)[None], _profile(cur_part, 1, trend_width)[None]
    )
    return shift_x + float(fine_x), shift_y + float(fine_y)


@dataclass(frozen=True)
class _Reference:
    data: FloatArray


class ProjectedOffsets(ReferenceOffsets[_Reference]):
    """Offsets from the frame's row and column sums cross-correlated with the reference's.

    Needs no source detection, so it works on fields too crowded or too faint to detect single
    stars, but every star (and defect) counts: fixed patterns pull towards zero offset.

    Parameters
    ----------
    max_shift
        Largest offset searched (pixels).
    trend_width
        Running-median width (pixels) removing sky and vignetting from the profiles; several
        times the star FWHM.
    reset_keywords
        Header keywords whose change starts a new reference.
    """

    def __init__(
        self,
        *,
        max_shift: int = 50,
        trend_width: int = 31,
        reset_keywords: Sequence[str] = DEFAULT_RESET_KEYWORDS,
        **kwargs: Any,
    ) -> None:
        super().__init__(reset_keywords=reset_keywords, **kwargs)
        require(max_shift >= 1, "max_shift", f"must be >= 1, got {max_shift}")
        require(trend_width >= 3, "trend_width", f"must be >= 3, got {trend_width}")
        self.max_shift = max_shift
        self.trend_width = trend_width

    def _blocking_reference(self, image: Image) -> _Reference:
        return _Reference(np.asarray(image.data, np.float64))

    def _blocking_offsets(self, reference: _Reference, image: Image) -> tuple[float, float]:
        return projected_offsets(
            reference.data,
            np.asarray(image.data, np.float64),
            max_shift=self.max_shift,
            trend_width=self.trend_width,
        )
