"""Combining a stack of frames into one, rejecting outliers (cosmic rays, satellites) per pixel."""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt
from astropy.stats import sigma_clip  # type: ignore[import-untyped]
from astropy.utils.exceptions import AstropyUserWarning  # type: ignore[import-untyped]

from nightcrew.images.errors import ImageDataError

__all__ = ["combine_frames"]

Float32Array = npt.NDArray[np.float32]

#: Rows combined at once: bounds the temporary memory of a stack to ~ frames x 256 x width.
_CHUNK_ROWS = 256


def combine_frames(
    frames: Sequence[npt.ArrayLike],
    *,
    method: str = "mean",
    sigma: float = 3.0,
    scales: Sequence[float] | None = None,
) -> tuple[Float32Array, Float32Array]:
    """Combine frames pixel by pixel: sigma-clipped ``mean`` or ``median``.

    Each frame may be divided by its entry in ``scales`` first (flats of different brightness).
    Returns the combined frame and its 1-sigma uncertainty (standard error of the kept values;
    for a median the mean's error times 1.253). A pixel whose values are all rejected falls back
    to the plain median of the stack. With fewer than three frames nothing is clipped.

    Raises:
        ImageDataError: no frames, frames of different shapes, or a bad ``method``/``scales``.
    """
    if method not in ("mean", "median"):
        raise ImageDataError(f"method must be 'mean' or 'median', got {method!r}")
    if not frames:
        raise ImageDataError("no frames to combine")
    arrays = [np.asarray(frame) for frame in frames]
    shape = arrays[0].shape
    if len(shape) != 2 or any(a.shape != shape for a in arrays):
        raise ImageDataError(
            f"frames to combine must be 2-D of one shape, got {sorted({a.shape for a in arrays})}"
        )
    if scales is not None and (
        len(scales) != len(arrays) or not all(np.isfinite(s) and s > 0 for s in scales)
    ):
        raise ImageDataError(f"scales must be one positive number per frame, got {list(scales)}")
    factors = np.ones(len(arrays), np.float32) if scales is None else 1.0 / np.asarray(scales, np.float32)
    combined = np.empty(shape, np.float32)
    error = np.empty(shape, np.float32)
    for start in range(0, shape[0], _CHUNK_ROWS):
        rows = slice(start, min(start + _CHUNK_ROWS, shape[0]))
        stack = np.stack([a[rows].astype(np.float32) * f for a, f in zip(arrays, factors, strict=True)])
        combined[rows], error[rows] = _combine_stack(stack, method, sigma)
    return combined, error


def _combine_stack(stack: Float32Array, method: str, sigma: float) -> tuple[Float32Array, Float32Array]:
    n = stack.shape[0]
    if n >= 3:
        with warnings.catch_warnings():
            # All-rejected pixels are expected now and then; they are handled below.
            warnings.simplefilter("ignore", AstropyUserWarning)
            clipped = sigma_clip(stack, sigma=sigma, axis=0, maxiters=3, cenfunc="median", stdfunc="mad_std")
        values = np.ma.masked_array(stack, mask=np.ma.getmaskarray(clipped))
    else:
        values = np.ma.masked_array(stack, mask=np.zeros_like(stack, dtype=bool))
    kept = values.count(axis=0)
    if method == "median":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all-rejected pixels: handled below
            centre = np.ma.masked_invalid(np.nanmedian(np.ma.filled(values, np.nan), axis=0))
    else:
        centre = values.mean(axis=0)
    spread = values.std(axis=0, ddof=1) if n >= 2 else np.ma.zeros(stack.shape[1:])
    with np.errstate(divide="ignore", invalid="ignore"):
        error = np.ma.filled(spread, 0.0) / np.sqrt(np.maximum(kept, 1))
    if method == "median":
        error = error * 1.253  # the median's standard error for normal noise
    fallback = np.median(stack, axis=0)
    result = np.where(kept > 0, np.ma.filled(centre, 0.0), fallback)
    return result.astype(np.float32), np.nan_to_num(error).astype(np.float32)
