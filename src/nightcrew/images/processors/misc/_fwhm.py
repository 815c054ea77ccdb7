"""FWHM (seeing) measurement: circular Moffat fits to good stars, median in pixels and arcsec."""

from __future__ import annotations

import asyncio
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt
from scipy import optimize  # type: ignore[import-untyped]

from nightcrew.images.errors import NoStarsError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require
from nightcrew.images.processors._shared import estimate_background, float_data, saturation_level
from nightcrew.images.processors.detection import detect_sources_sep

__all__ = ["FWHM_KEY", "FwhmMeasurement", "MeasureFwhm", "measure_fwhm", "moffat_fwhm"]

FloatArray = npt.NDArray[np.float64]
FWHM_KEY = "fwhm"


@dataclass(frozen=True)
class FwhmMeasurement:
    """Median star FWHM: pixels, arcsec (None without a pixel scale), and the number of stars."""

    fwhm_px: float
    fwhm_arcsec: float | None
    stars: int


def moffat_fwhm(stamp: FloatArray, x0: float, y0: float) -> float | None:
    """FWHM (pixels) of a circular Moffat fitted to a background-free ``stamp`` near (x0, y0).

    The model ``A (1 + r^2/alpha^2)^-beta`` has ``FWHM = 2 alpha sqrt(2^(1/beta) - 1)``; its free
    ``beta`` lets it describe both seeing-limited (beta ~ 3) and Gaussian-like (large beta)
    stars. Returns None if the fit fails or ends at a bound.
    """
    rows, cols = np.indices(stamp.shape, dtype=np.float64)
    values = stamp.ravel()
    peak = float(stamp.max())
    if peak <= 0:
        return None

    dx_all, dy_all = cols.ravel(), rows.ravel()

    def residuals(p: FloatArray) -> FloatArray:
        amplitude, x, y, alpha, beta = p
        r2 = (dx_all - x) ** 2 + (dy_all - y) ** 2
        return np.asarray(amplitude * (1.0 + r2 / alpha**2) ** -beta - values, np.float64)

    def jacobian(p: FloatArray) -> FloatArray:
        # Analytic: a numerical Jacobian took most of a seeing measurement's time.
        amplitude, x, y, alpha, beta = p
        dx, dy = dx_all - x, dy_all - y
        r2 = dx**2 + dy**2
        u = 1.0 + r2 / alpha**2
        profile = u**-beta
        slope = 2.0 * amplitude * beta * profile / u / alpha**2  # -d(model)/d(r2) x 2
        return np.column_stack(
            (profile, slope * dx, slope * dy, slope * r2 / alpha, -amplitude * profile * np.log(u))
        )

    start = np.array([peak, x0, y0, 2.0, 3.0])
    lower = np.array([0.0, x0 - 2.0, y0 - 2.0, 0.2, 1.01])
    upper = np.array([10.0 * peak, x0 + 2.0, y0 + 2.0, 50.0, 30.0])
    try:
        fit = optimize.least_squares(residuals, start, jac=jacobian, bounds=(lower, upper), x_scale="jac")
    except (ValueError, np.linalg.LinAlgError):
        return None
    _, _, _, alpha, beta = fit.x
    if (
        not fit.success
        or np.any(np.isclose(fit.x[3:], lower[3:]))
        or np.any(np.isclose(fit.x[3:], upper[3:]))
    ):
        return None
    return float(2.0 * alpha * math.sqrt(2.0 ** (1.0 / beta) - 1.0))


def measure_fwhm(
    data: FloatArray,
    x: FloatArray,
    y: FloatArray,
    *,
    half_size: int,
) -> FloatArray:
    """FWHM (pixels) of the stars at (x, y) in background-free ``data``; NaN where a fit failed."""
    rows, cols = data.shape
    result = np.full(len(x), np.nan)
    for k, (xs, ys) in enumerate(zip(x, y, strict=True)):
        cx, cy = round(float(xs)), round(float(ys))
        if cx < half_size or cy < half_size or cx >= cols - half_size or cy >= rows - half_size:
            continue
        stamp = data[cy - half_size : cy + half_size + 1, cx - half_size : cx + half_size + 1]
        fwhm = moffat_fwhm(stamp, xs - cx + half_size, ys - cy + half_size)
        if fwhm is not None:
            result[k] = fwhm
    return result


def central_window(shape: tuple[int, ...], side: int) -> tuple[slice, slice]:
    """Row and column slices of the central ``side`` x ``side`` square of an image of ``shape``."""
    rows, cols = shape[0], shape[1]
    top, left = max(0, (rows - side) // 2), max(0, (cols - side) // 2)
    return slice(top, top + side), slice(left, left + side)


class MeasureFwhm(ImageProcessor):
    """Median FWHM of good stars, into ``metadata["fwhm"]`` and the header (``FWHM``, ``FWHMPIX``).

    Good stars: unflagged (not saturated, blended or truncated), with peak at least
    ``min_peak_snr`` times the background noise, not crowded by another source within
    ``half_size`` pixels; the brightest ``max_stars`` are fitted.

    Parameters
    ----------
    max_stars
        Most stars fitted (the brightest good ones).
    half_size
        Half size (pixels) of the fitted box; about 3 FWHM.
    min_peak_snr
        Minimum peak over background noise.
    detection_threshold
        Threshold (sigma) when no catalog is present and detection runs here.
    window
        When detection runs here: side (pixels) of the central square searched and measured; None
        for the whole frame. A seeing monitor needs a handful of stars, and detecting them costs
        in proportion to the pixels (about 0.2 s for a crowded 2k frame, holding the interpreter).
    """

    def __init__(
        self,
        *,
        max_stars: int = 50,
        half_size: int = 8,
        min_peak_snr: float = 20.0,
        detection_threshold: float = 10.0,
        window: int | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        require(max_stars >= 1, "max_stars", f"must be >= 1, got {max_stars}")
        require(half_size >= 3, "half_size", f"must be >= 3, got {half_size}")
        require(min_peak_snr > 0, "min_peak_snr", f"must be > 0, got {min_peak_snr}")
        require(window is None or window > 4 * half_size, "window", f"must be > 4 half_size, got {window}")
        self.max_stars = max_stars
        self.half_size = half_size
        self.min_peak_snr = min_peak_snr
        self.detection_threshold = detection_threshold
        self.window = window

    async def __call__(self, image: Image) -> Image:
        fwhm_px, stars = await asyncio.to_thread(self._blocking_measure, image)
        scale = image.pixel_scale
        fwhm_arcsec = None if scale is None else fwhm_px * scale
        result = image.copy()
        result.metadata[FWHM_KEY] = FwhmMeasurement(fwhm_px, fwhm_arcsec, stars)
        result.header["FWHMPIX"] = (round(fwhm_px, 3), "Median star FWHM [px]")
        if fwhm_arcsec is not None:
            result.header["FWHM"] = (round(fwhm_arcsec, 3), "Median star FWHM [arcsec]")
        return result

    def _blocking_measure(self, image: Image) -> tuple[float, int]:
        data, mask = float_data(image), image.mask
        catalog = image.catalog
        if catalog is None:
            if self.window is not None:
                rows, cols = central_window(data.shape, self.window)
                data = np.ascontiguousarray(data[rows, cols])
                mask = None if mask is None else mask[rows, cols]
            catalog = detect_sources_sep(
                data.copy(),
                mask,
                threshold=self.detection_threshold,
                saturation=saturation_level(image, None),
                windowed_centroids=False,  # the Moffat fit finds the centre itself
            )
        background = estimate_background(data, mask)
        data -= background.level
        x, y = np.asarray(catalog["x"], np.float64), np.asarray(catalog["y"], np.float64)
        peak = np.asarray(catalog["peak"], np.float64)
        good = (np.asarray(catalog["flags"]) == 0) & (peak >= self.min_peak_snr * background.global_rms)
        if len(x) > 1:
            distance = np.hypot(x[:, None] - x[None, :], y[:, None] - y[None, :])
            np.fill_diagonal(distance, np.inf)
            good &= distance.min(axis=1) > self.half_size
        chosen = np.flatnonzero(good)[np.argsort(-peak[good], kind="stable")][: self.max_stars]
        fwhm = measure_fwhm(data, x[chosen], y[chosen], half_size=self.half_size)
        fwhm = fwhm[np.isfinite(fwhm)]
        if len(fwhm) == 0:
            raise NoStarsError("no star good enough for a FWHM measurement")
        return float(np.median(fwhm)), len(fwhm)
