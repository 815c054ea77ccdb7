"""Focus series, pure: how sharp one frame is, and the best focus of a series from a hyperbola fit.

Two per-frame measures, both "smaller is sharper", both in pixels:

* :func:`projection_width` collapses the frame along x and along y and measures the width of the
  central peak of each profile's *autocorrelation*. A profile of a star field is a sum of star
  profiles at random places; its autocorrelation always peaks at lag 0 with the width of one star
  (times sqrt 2 for Gaussian-like stars, corrected here), whatever the stars' positions. Cheap, no
  detection needed, works on defocused donuts; crowded fields widen it a little (cross terms).
* :func:`photometry_width` is the median FWHM of the unflagged, well-exposed stars of a source
  catalog (from :func:`nightcrew.images.processors.detection.detect_sources_sep`), leaving out
  the :func:`point_defects`: focus frames are raw, and their hot pixels and cosmic rays are sharp
  "stars" that do not blur with defocus - out of focus, where few real stars stand out of a
  bright (twilight) sky, they would outnumber them and pull the median down to their own width.

The series is fitted with the hyperbola ``w(f) = sqrt(a² + (b (f - f0))²)`` — seeing and optics
set the minimum ``a``, defocus blur grows linearly with ``|f - f0|`` — by least squares
(:func:`fit_focus_hyperbola`). The uncertainty of ``f0`` is from the fit's covariance scaled by the
residual variance. A minimum outside the focus range of the series is not a measurement but an
extrapolation, so :func:`fit_focus_hyperbola` refuses it with :class:`FocusOutsideSeriesError`.
It also refuses a fit that does not describe the widths - a best focus less certain than a
fraction of the step (:data:`MAX_ERROR_PER_STEP`), or widths scattered about the fitted V by more
than a fraction of its depth (:data:`MAX_SCATTER`) - with :class:`FocusSeriesError`: moving the
focuser to a garbage "best focus" is worse than keeping the focus it had.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import optimize  # type: ignore[import-untyped]

from nightcrew.errors import InvalidArgumentError

__all__ = [
    "FocusFit",
    "FocusOutsideSeriesError",
    "FocusSeriesError",
    "fit_focus_hyperbola",
    "photometry_width",
    "point_defects",
    "projection_width",
    "series_positions",
]

FloatArray = npt.NDArray[np.float64]

#: FWHM of a Gaussian over the FWHM of its autocorrelation (the autocorrelation is sqrt 2 wider).
_ACF_TO_STAR = 1.0 / math.sqrt(2.0)
#: Fewest frames a hyperbola (3 parameters) needs to leave a residual to judge it by.
MIN_FRAMES = 4
#: A source whose 3x3 median keeps less than this fraction of its peak is a hot pixel or cosmic ray
#: (a star 1.5 px wide keeps a third of it, 2 px half).
DEFECT_PEAK_KEPT = 0.2
#: Row and column offsets of a 3x3 box.
_BOX_ROWS, _BOX_COLS = (a.ravel() for a in np.mgrid[-1:2, -1:2])
#: A best focus less certain than this fraction of the series' step is refused (good V: 0.05-0.2).
MAX_ERROR_PER_STEP = 0.5
#: Widths scattered (RMS) about the fitted V by more than this fraction of its depth - the rise
#: from the minimum to the series' farthest frame - do not form a V (good series: ~0.03).
MAX_SCATTER = 0.15


class FocusSeriesError(InvalidArgumentError):
    """A focus series cannot give a best focus (too few good frames, a failed fit)."""


class FocusOutsideSeriesError(FocusSeriesError):
    """The fitted minimum lies outside the focus range of the series: move the series and retry."""


@dataclass(frozen=True)
class FocusFit:
    """A fitted focus hyperbola ``w(f) = sqrt(a² + (b (f - focus))²)``.

    Attributes:
        focus: Best focus (units of the series' focus values).
        error: 1-sigma uncertainty of ``focus``.
        min_width: ``a``, the width at best focus (units of the widths).
        slope: ``b``, width growth per focus unit far from focus.
        rms: RMS residual of the fit (units of the widths).
    """

    focus: float
    error: float
    min_width: float
    slope: float
    rms: float

    def width_at(self, focus: float) -> float:
        return math.hypot(self.min_width, self.slope * (focus - self.focus))


# --- per-frame measures ------------------------------------------------------------------------


def projection_width(data: npt.ArrayLike, mask: npt.ArrayLike | None = None) -> float:
    """Typical star FWHM in pixels from the autocorrelation of the x and y projections of ``data``.

    Bad pixels (``mask`` True) are replaced by the frame's median before collapsing.

    Raises:
        FocusSeriesError: The frame holds no peak (flat or too small).
    """
    pixels = np.array(data, dtype=np.float64)
    if pixels.ndim != 2 or min(pixels.shape) < 8:
        raise FocusSeriesError(f"need a 2-D frame of at least 8x8 pixels, got shape {pixels.shape}")
    if mask is not None:
        pixels[np.asarray(mask, dtype=bool)] = np.median(pixels)
    widths = [_acf_width(pixels.sum(axis=axis)) for axis in (0, 1)]
    return float(np.mean(widths)) * _ACF_TO_STAR


def _acf_width(profile: FloatArray) -> float:
    """FWHM (pixels) of the central peak of the autocorrelation of ``profile``."""
    # A running median far wider than any star removes the sky and its gradients.
    window = max(3, len(profile) // 4) | 1
    padded = np.pad(profile, window // 2, mode="reflect")
    baseline = np.median(np.lib.stride_tricks.sliding_window_view(padded, window), axis=1)
    signal = np.clip(profile - baseline, 0.0, None)  # stars only add light
    n = len(signal)
    spectrum = np.fft.rfft(signal, 2 * n)  # zero-padded: a linear, not circular, correlation
    acf = np.fft.irfft(spectrum * np.conj(spectrum))[:n]
    if not acf[0] > 0:
        raise FocusSeriesError("the frame shows no stars (flat projection)")
    acf = acf / acf[0]
    below = np.flatnonzero(acf < 0.5)
    if len(below) == 0:
        raise FocusSeriesError("the projection's peak fills the frame: stars too wide to measure")
    k = int(below[0])
    # Interpolate the half-maximum crossing between lags k-1 and k; the peak is symmetric.
    half = (k - 1) + (acf[k - 1] - 0.5) / (acf[k - 1] - acf[k])
    return 2.0 * float(half)


def point_defects(
    residual: npt.ArrayLike, x: npt.ArrayLike, y: npt.ArrayLike, peak: npt.ArrayLike
) -> npt.NDArray[np.bool_]:
    """True for the sources at (``x``, ``y``) that are a pixel or a thin track: hot pixels, cosmic rays.

    A 3x3 median outvotes such a defect but keeps much of a star's peak, so a source whose median
    around its position in ``residual`` (the frame minus its background) keeps less than
    :data:`DEFECT_PEAK_KEPT` of its ``peak`` is no star.
    """
    data = np.asarray(residual, dtype=np.float64)
    rows = np.clip(np.rint(np.asarray(y, dtype=np.float64)).astype(np.int64), 0, data.shape[0] - 1)
    cols = np.clip(np.rint(np.asarray(x, dtype=np.float64)).astype(np.int64), 0, data.shape[1] - 1)
    box_rows = np.clip(rows[:, None] + _BOX_ROWS[None, :], 0, data.shape[0] - 1)
    box_cols = np.clip(cols[:, None] + _BOX_COLS[None, :], 0, data.shape[1] - 1)
    kept = np.median(data[box_rows, box_cols], axis=1)
    return np.asarray(~(kept >= DEFECT_PEAK_KEPT * np.asarray(peak, dtype=np.float64)), dtype=np.bool_)


def photometry_width(
    fwhm: npt.ArrayLike,
    flags: npt.ArrayLike,
    peak: npt.ArrayLike,
    *,
    noise: float,
    min_peak_snr: float = 10.0,
    min_stars: int = 3,
    defects: npt.ArrayLike | None = None,
) -> float:
    """Median FWHM (pixels) of the catalog's unflagged stars with ``peak >= min_peak_snr * noise``.

    ``defects`` (e.g. from :func:`point_defects`) is True for the sources that are no stars.

    Raises:
        FocusSeriesError: Fewer than ``min_stars`` stars qualify.
    """
    widths = np.asarray(fwhm, dtype=np.float64)
    good = (np.asarray(flags) == 0) & (np.asarray(peak, dtype=np.float64) >= min_peak_snr * noise)
    if defects is not None:
        good &= ~np.asarray(defects, dtype=bool)
    good &= np.isfinite(widths) & (widths > 0)
    if int(good.sum()) < min_stars:
        raise FocusSeriesError(
            f"only {int(good.sum())} good stars (need {min_stars} with peak >= {min_peak_snr:g} sigma)"
        )
    return float(np.median(widths[good]))


# --- the series --------------------------------------------------------------------------------


def series_positions(
    centre: float, count: int, step: float, reachable: tuple[float, float] | None = None
) -> list[float]:
    """Focus positions of a series: ``count`` of them ``step`` apart, centred on ``centre``, but
    shifted as a whole into ``reachable`` (low, high) where the centre is too close to an end (a
    focuser resting at its end still gets a full series). FocusSeriesError when the series is
    longer than the reachable range."""
    half = (count - 1) / 2.0 * step
    if reachable is None:
        return [centre - half + i * step for i in range(count)]
    low, high = reachable
    if 2.0 * half > high - low:
        raise FocusSeriesError(
            f"a series of {count} frames {step:g} mm apart spans {2.0 * half:g} mm, more than the "
            f"focuser's range {low:g}..{high:g} mm"
        )
    start = min(max(centre - half, low), high - 2.0 * half)
    return [min(high, max(low, start + i * step)) for i in range(count)]  # no rounding past an end


def fit_focus_hyperbola(
    focus: Sequence[float],
    width: Sequence[float],
    *,
    max_error: float | None = None,
    max_scatter: float = MAX_SCATTER,
) -> FocusFit:
    """Best focus of a series from a least-squares hyperbola fit, refused unless the widths form a V.

    Args:
        focus: Focus position of each frame.
        width: Width (e.g. FWHM) measured on each frame, same length; NaN for a failed frame.
        max_error: Largest accepted uncertainty of the best focus; None: :data:`MAX_ERROR_PER_STEP`
            times the median step between the series' positions.
        max_scatter: Largest accepted RMS residual as a fraction of the fitted V's depth.

    Raises:
        FocusSeriesError: Fewer than :data:`MIN_FRAMES` good frames, a series at one position, a
            fit that does not converge, or one that does not describe the widths (see above).
        FocusOutsideSeriesError: The minimum lies outside the series' focus range.
    """
    f = np.asarray(focus, dtype=np.float64)
    w = np.asarray(width, dtype=np.float64)
    if f.shape != w.shape or f.ndim != 1:
        raise FocusSeriesError(f"need two equally long 1-D sequences, got {f.shape} and {w.shape}")
    good = np.isfinite(f) & np.isfinite(w) & (w > 0)
    f, w = f[good], w[good]
    if len(f) < MIN_FRAMES:
        raise FocusSeriesError(f"only {len(f)} usable frames, need at least {MIN_FRAMES}")
    lo, hi = float(f.min()), float(f.max())
    if not hi > lo:
        raise FocusSeriesError(f"all frames at one focus position ({lo:g}): no series to fit")
    span = hi - lo

    def residuals(p: FloatArray) -> FloatArray:
        f0, a, b = p
        return np.asarray(np.hypot(a, b * (f - f0)) - w, np.float64)

    # Start at the sharpest frame; the slope from the widest frame's distance to it.
    best = int(np.argmin(w))
    far = int(np.argmax(np.abs(f - f[best])))
    slope = max(float(w[far] - w[best]), 1e-6 * float(w.max())) / max(abs(f[far] - f[best]), span / 10)
    start = np.array([f[best], float(w[best]), slope])
    lower = np.array([lo - 2 * span, 0.0, 0.0])
    upper = np.array([hi + 2 * span, np.inf, np.inf])
    fit = optimize.least_squares(residuals, start, bounds=(lower, upper), x_scale="jac")
    if not fit.success:
        raise FocusSeriesError(f"the hyperbola fit did not converge: {fit.message}")
    f0, a, b = (float(v) for v in fit.x)
    if not lo <= f0 <= hi:
        raise FocusOutsideSeriesError(
            f"best focus {f0:.4f} from the fit lies outside the series {lo:.4f}..{hi:.4f}: "
            "centre the series nearer to focus and repeat"
        )
    dof = len(f) - 3
    rms = float(np.sqrt(np.mean(fit.fun**2)))
    variance = float(np.sum(fit.fun**2)) / dof if dof > 0 else 0.0
    try:
        covariance = np.linalg.inv(fit.jac.T @ fit.jac) * variance
        error = float(np.sqrt(covariance[0, 0]))
    except np.linalg.LinAlgError:
        error = math.inf
    if not math.isfinite(error):
        raise FocusSeriesError("the hyperbola fit is degenerate (no curvature): the series is too flat")
    result = FocusFit(focus=f0, error=error, min_width=abs(a), slope=abs(b), rms=rms)
    _check_plausible(result, f, max_error, max_scatter)
    return result


def _check_plausible(fit: FocusFit, focus: FloatArray, max_error: float | None, max_scatter: float) -> None:
    """Raise FocusSeriesError unless ``fit`` pins the focus down and describes the widths."""
    if max_error is None:
        max_error = MAX_ERROR_PER_STEP * float(np.median(np.diff(np.unique(focus))))
    if not fit.error <= max_error:
        raise FocusSeriesError(
            f"best focus {fit.focus:.4f} ± {fit.error:.4f} is too uncertain (accepted: ± {max_error:.4f}): "
            "the widths do not form a clear V"
        )
    depth = fit.width_at(float(focus[np.argmax(np.abs(focus - fit.focus))])) - fit.min_width
    if not fit.rms <= max_scatter * depth:
        raise FocusSeriesError(
            f"the widths scatter by {fit.rms:.2f} about a fitted V only {depth:.2f} deep "
            f"(accepted: {max_scatter:g} of the depth): no consistent V"
        )
