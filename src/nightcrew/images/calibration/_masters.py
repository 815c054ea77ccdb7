"""Master bias, dark and flat from stacks of raw frames, and their application, on arrays.

Conventions (all in ADU, float32):

- master bias: the combined bias frames.
- master dark: the combined dark frames minus the master bias — dark charge over the darks'
  exposure time, scaled linearly to a science frame's exposure time when applied.
- master flat: each flat minus bias and scaled dark, divided by its own median (so flats of
  different brightness combine), then combined and normalised to a median of 1.
- calibrated = (raw - bias - dark * t_science / t_dark) / flat.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from nightcrew.images.calibration._combine import combine_frames
from nightcrew.images.errors import ImageDataError

__all__ = ["Combined", "calibrate_pixels", "master_bias", "master_dark", "master_flat"]

Float32Array = npt.NDArray[np.float32]

#: Flat values below this (after normalisation) mark dead or fully vignetted pixels.
MIN_FLAT = 0.05


@dataclass(frozen=True)
class Combined:
    """A master: pixels, their 1-sigma uncertainty and how many frames went into it."""

    data: Float32Array
    uncertainty: Float32Array
    n_frames: int


def master_bias(frames: Sequence[npt.ArrayLike], *, sigma: float = 3.0) -> Combined:
    """Sigma-clipped mean of bias frames."""
    data, error = combine_frames(frames, method="mean", sigma=sigma)
    return Combined(data, error, len(frames))


def master_dark(frames: Sequence[npt.ArrayLike], bias: Combined, *, sigma: float = 3.0) -> Combined:
    """Sigma-clipped mean of dark frames (all of one exposure time) minus the master bias."""
    data, error = combine_frames(frames, method="mean", sigma=sigma)
    _check_shape(data, bias.data, "bias")
    return Combined(data - bias.data, np.hypot(error, bias.uncertainty), len(frames))


def master_flat(
    frames: Sequence[npt.ArrayLike],
    bias: Combined,
    *,
    dark: Combined | None = None,
    dark_exposure_s: float = 0.0,
    exposure_times_s: Sequence[float] | None = None,
    sigma: float = 3.0,
) -> Combined:
    """Normalised flat (median 1) from flat frames of one filter; see the module docstring.

    Raises:
        ImageDataError: a flat without signal, or frames not matching the bias/dark.
    """
    times = list(exposure_times_s) if exposure_times_s is not None else [0.0] * len(frames)
    if len(times) != len(frames):
        raise ImageDataError(f"{len(frames)} flats but {len(times)} exposure times")
    corrected = [
        calibrate_pixels(f, bias=bias, dark=dark, dark_exposure_s=dark_exposure_s, exposure_s=t)[0]
        for f, t in zip(frames, times, strict=True)
    ]
    levels = [float(np.median(c)) for c in corrected]
    if any(not np.isfinite(level) or level <= 0 for level in levels):
        raise ImageDataError(f"flat frames need a positive signal above bias, got median levels {levels}")
    data, error = combine_frames(corrected, method="mean", sigma=sigma, scales=levels)
    norm = float(np.median(data))
    return Combined(data / np.float32(norm), error / np.float32(norm), len(frames))


def calibrate_pixels(
    raw: npt.ArrayLike,
    *,
    bias: Combined,
    dark: Combined | None = None,
    dark_exposure_s: float = 0.0,
    flat: Combined | None = None,
    exposure_s: float = 0.0,
) -> tuple[Float32Array, npt.NDArray[np.bool_]]:
    """A calibrated frame (see the module docstring) and the mask of pixels the flat cannot correct.

    Raises:
        ImageDataError: masters of another shape, or a dark without a positive exposure time.
    """
    data = np.asarray(raw, dtype=np.float32)
    _check_shape(data, bias.data, "bias")
    result = data - bias.data
    if dark is not None:
        _check_shape(data, dark.data, "dark")
        if dark_exposure_s <= 0:
            raise ImageDataError(f"a master dark needs its positive exposure time, got {dark_exposure_s}")
        result -= dark.data * np.float32(exposure_s / dark_exposure_s)
    bad = np.zeros(data.shape, dtype=bool)
    if flat is not None:
        _check_shape(data, flat.data, "flat")
        bad = ~(flat.data >= MIN_FLAT)  # also True for NaN
        result /= np.where(bad, np.float32(1.0), flat.data)
    return result, bad


def _check_shape(data: npt.NDArray[np.generic], master: Float32Array, name: str) -> None:
    if data.shape != master.shape:
        raise ImageDataError(f"master {name} has shape {master.shape}, the frame {data.shape}")
