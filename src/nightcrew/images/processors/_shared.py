"""Pixel helpers shared by the processors: float data and SEP background estimation."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
import sep  # type: ignore[import-not-found]

from nightcrew.images.errors import ImageDataError
from nightcrew.images.image import Image

__all__ = ["Background", "estimate_background", "float_data", "saturation_level"]

FloatArray = npt.NDArray[np.float64]

# The object-pixel stack grows as frames need it: see detection._sep._extract.
sep.set_sub_object_limit(4096)


@dataclass(frozen=True)
class Background:
    """A background model: level and 1-sigma noise per pixel (data units), and the global noise."""

    level: FloatArray
    rms: FloatArray
    global_rms: float


def float_data(image: Image) -> FloatArray:
    """A writable, C-contiguous float64 copy of the image's pixels (what SEP needs)."""
    return np.ascontiguousarray(image.data, dtype=np.float64).copy()


def estimate_background(
    data: FloatArray, mask: npt.NDArray[np.bool_] | None = None, *, box_size: int = 64, filter_size: int = 3
) -> Background:
    """SEP's mesh background (sigma-clipped mode per ``box_size`` box, median-filtered, splined).

    Raises
    ------
    ImageDataError
        The frame is smaller than one box, or every pixel is masked.
    """
    if min(data.shape) < 2:
        raise ImageDataError(f"frame {data.shape} is too small for a background estimate")
    if mask is not None and bool(mask.all()):
        raise ImageDataError("every pixel is masked")
    box = max(2, min(box_size, *data.shape))
    sep_mask = None if mask is None else np.ascontiguousarray(mask, dtype=np.uint8)
    model = sep.Background(data, mask=sep_mask, bw=box, bh=box, fw=filter_size, fh=filter_size)
    return Background(level=model.back(), rms=model.rms(), global_rms=float(model.globalrms))


def saturation_level(image: Image, default: float | None) -> float | None:
    """Saturation level (data units): the header's ``SATURATE`` or ``default``."""
    value: Any = image.header.get("SATURATE", default)
    return float(value) if isinstance(value, int | float) and not isinstance(value, bool) else default
