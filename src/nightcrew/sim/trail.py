"""Motion during an exposure: stars trailed when the mount does not track them, and the sub-times
at which a moving body is drawn.

A frame whose pointing moves (the mount follows a moving body at offset rates) shows every star
along the same path in pixels (the field is small: the path of the field's centre stands for all),
so the trailed star image is the still one convolved with a *trail kernel*: the path sampled at
equal times, each sample spread bilinearly over its four nearest pixels. A body is drawn as a
stamp per sample instead, as its path differs from the stars'.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
from scipy import signal  # type: ignore[import-untyped]

__all__ = ["MAX_SAMPLES", "sample_count", "sample_fractions", "trail", "trail_kernel"]

FloatArray = npt.NDArray[np.float64]
Float32Array = npt.NDArray[np.float32]

#: Most samples along an exposure's path (a satellite's long trail is then dotted at > 0.25 px).
MAX_SAMPLES = 20_000
#: Path lengths below this (pixels) are no trail at all.
_STILL_PX = 0.05


def sample_count(path_px: float, *, step_px: float = 0.25) -> int:
    """Samples that cover a path of ``path_px`` pixels every ``step_px`` (1 for a still one)."""
    if not math.isfinite(path_px) or path_px <= 0:
        return 1
    return max(1, min(MAX_SAMPLES, math.ceil(path_px / step_px) + 1))


def sample_fractions(count: int) -> FloatArray:
    """The mid-times of ``count`` equal parts of an exposure, as fractions of it (0..1)."""
    return (np.arange(count, dtype=np.float64) + 0.5) / count


def trail_kernel(dx: FloatArray, dy: FloatArray) -> Float32Array:
    """A kernel (odd sides, centre = no shift) holding a point moved by (``dx``, ``dy``) pixels,
    an equal share of light at each sample; it sums to 1."""
    half_x = math.ceil(float(np.max(np.abs(dx)))) + 1
    half_y = math.ceil(float(np.max(np.abs(dy)))) + 1
    kernel = np.zeros((2 * half_y + 1, 2 * half_x + 1), dtype=np.float64)
    x, y = dx + half_x, dy + half_y
    x0, y0 = np.floor(x).astype(np.int64), np.floor(y).astype(np.int64)
    fx, fy = x - x0, y - y0
    for ox, oy, weight in (
        (0, 0, (1 - fx) * (1 - fy)),
        (1, 0, fx * (1 - fy)),
        (0, 1, (1 - fx) * fy),
        (1, 1, fx * fy),
    ):
        np.add.at(kernel, (y0 + oy, x0 + ox), weight)
    return np.asarray(kernel / kernel.sum(), dtype=np.float32)


def trail(image: Float32Array, dx: FloatArray, dy: FloatArray) -> Float32Array:
    """``image`` with everything in it moved along (``dx``, ``dy``) pixels during the exposure
    (light carried off the edge is lost, as on a real chip)."""
    if len(dx) == 0 or float(np.max(np.hypot(dx, dy))) < _STILL_PX:
        return image
    kernel = trail_kernel(np.asarray(dx, np.float64), np.asarray(dy, np.float64))
    trailed = signal.oaconvolve(image, kernel, mode="same")
    # FFT rounding leaves values a hair below zero where there is no light.
    return np.asarray(np.maximum(trailed, 0.0), dtype=np.float32)
