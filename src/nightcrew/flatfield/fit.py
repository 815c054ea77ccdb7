"""Fitting exposure-time functions ``exp(a*(h + b))`` to a night's twilight flats.

Every flat tells how long it *would* have needed to reach the target level at its solar altitude:
``t_target = t * (target - bias) / (level - bias)``. The twilight sky fades exponentially with the
Sun's depression, so ``ln t_target`` is a straight line in ``h``; a least-squares line (with one
round of 3-sigma clipping, never below 5 %) gives ``a`` (slope) and ``b`` (minus the altitude where one second
suffices), i.e. ``t(h) = exp(a*(h + b))``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

__all__ = ["ExposureFit", "FlatSample", "fit_exposure_function", "target_exposure_time"]

FloatArray = npt.NDArray[np.float64]

#: Residuals in ln t below this (5 %) are never clipped, however well the other flats agree.
_MIN_CLIP = 0.05


@dataclass(frozen=True)
class FlatSample:
    """One flat: solar altitude (deg) at the exposure's start, exposure time (s), median level (ADU)."""

    sun_altitude: float
    exposure_time: float
    level: float


@dataclass(frozen=True)
class ExposureFit:
    """A fitted ``exp(slope*(h + offset))`` with what it was fitted from.

    Attributes:
        slope: ``a`` in 1/deg (negative: darker sky, longer exposures).
        offset: ``b`` in degrees.
        altitudes: Solar altitudes of the flats used (deg).
        times: Their exposure times scaled to the target level (s).
        rejected: How many flats the clipping left out.
        rms: RMS of the residuals in ln t (≈ relative error).
    """

    slope: float
    offset: float
    altitudes: FloatArray
    times: FloatArray
    rejected: int
    rms: float

    @property
    def expression(self) -> str:
        """The function as a configuration expression in ``h``."""
        sign = "+" if self.offset >= 0 else "-"
        return f"exp({self.slope:.4f}*(h {sign} {abs(self.offset):.3f}))"

    def __call__(self, sun_altitude: FloatArray | float) -> FloatArray:
        return np.asarray(np.exp(self.slope * (np.asarray(sun_altitude) + self.offset)), dtype=np.float64)


def target_exposure_time(sample: FlatSample, target: float, bias: float) -> float:
    """Seconds the flat would have needed to reach ``target`` (both levels including ``bias``)."""
    return sample.exposure_time * (target - bias) / (sample.level - bias)


def fit_exposure_function(samples: Sequence[FlatSample], target: float, bias: float) -> ExposureFit:
    """Fit ``exp(a*(h + b))`` to the flats' exposure times scaled to the target level.

    Raises:
        ValueError: Fewer than 3 usable flats, or all at the same solar altitude.
    """
    usable = [s for s in samples if s.level > bias and s.exposure_time > 0]
    if len(usable) < 3:
        raise ValueError(f"need at least 3 flats with signal above the bias, got {len(usable)}")
    h = np.array([s.sun_altitude for s in usable])
    log_t = np.log([target_exposure_time(s, target, bias) for s in usable])
    if np.ptp(h) < 1e-3:
        raise ValueError("all flats were taken at the same solar altitude: nothing to fit a slope to")
    keep = np.ones(len(h), dtype=bool)
    for _ in range(2):  # fit, clip at 3 sigma, refit
        slope, intercept = np.polyfit(h[keep], log_t[keep], 1)
        residuals = log_t - (slope * h + intercept)
        sigma = float(np.std(residuals[keep]))
        new_keep = np.abs(residuals) <= max(3.0 * sigma, _MIN_CLIP)
        if new_keep.sum() < 3 or np.array_equal(new_keep, keep):
            break
        keep = new_keep
    slope, intercept = np.polyfit(h[keep], log_t[keep], 1)
    rms = float(np.sqrt(np.mean((log_t[keep] - (slope * h[keep] + intercept)) ** 2)))
    if slope == 0:
        raise ValueError("the exposure times do not change with the solar altitude")
    return ExposureFit(
        slope=float(slope),
        offset=float(intercept / slope),
        altitudes=h[keep],
        times=np.exp(log_t[keep]),
        rejected=int((~keep).sum()),
        rms=rms,
    )
