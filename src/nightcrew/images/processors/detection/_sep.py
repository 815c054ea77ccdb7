"""Source detection with SEP (Source Extractor as a library): background, extraction, centroids."""

from __future__ import annotations

import asyncio
import math
import threading
from typing import Any

import numpy as np
import numpy.typing as npt
import sep  # type: ignore[import-not-found]
from astropy.table import Table  # type: ignore[import-untyped]

from nightcrew.images.errors import ImageDataError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require
from nightcrew.images.processors._shared import estimate_background, float_data, saturation_level
from nightcrew.images.processors.detection._catalog import FLAG_SATURATED, catalog_table

__all__ = ["SepSourceDetection", "detect_sources_sep"]

_SIGMA_PER_FWHM = 1.0 / (2.0 * math.sqrt(2.0 * math.log(2.0)))


def detect_sources_sep(
    data: npt.NDArray[np.float64],
    mask: npt.NDArray[np.bool_] | None = None,
    *,
    threshold: float = 4.0,
    min_area: int = 5,
    deblend_contrast: float = 0.005,
    box_size: int = 64,
    kernel_fwhm: float = 3.0,
    saturation: float | None = None,
    windowed_centroids: bool = True,
) -> Table:
    """Sources in ``data`` (raw pixels; the background is estimated and subtracted here).

    Parameters
    ----------
    data
        Writable, C-contiguous float64 pixels (see :func:`~.._shared.float_data`).
    mask
        True on bad pixels, which are ignored.
    threshold
        Detection threshold in sigma of the *filtered* image's noise (a matched-filter
        significance; 4 gives well under one false detection per megapixel).
    min_area
        Minimum number of connected pixels above the threshold.
    deblend_contrast
        SEP's minimum contrast for splitting blended sources (smaller splits more).
    box_size
        Background mesh size (pixels).
    kernel_fwhm
        FWHM (pixels) of the Gaussian matched filter applied before thresholding: close to the
        stars' FWHM finds the faintest stars (SEP's default 3x3 kernel misses faint wide stars).
    saturation
        Raw level (data units) at which a source is flagged :data:`FLAG_SATURATED`.
    windowed_centroids
        Refine positions with SEP's windowed centroids (a quarter of the time in crowded fields;
        callers that fit the stars anyway skip it).

    Returns
    -------
    Table
        The catalog (see :mod:`._catalog`), positions refined by SEP's windowed centroids; the
        FWHM comes from the isophotal second moments (a quick estimate: see
        :class:`~nightcrew.images.processors.misc.MeasureFwhm` for an accurate one).
    """
    background = estimate_background(data, mask, box_size=box_size)
    data -= background.level
    sep_mask = None if mask is None else np.ascontiguousarray(mask, dtype=np.uint8)
    kernel = gaussian_kernel(kernel_fwhm)
    # The threshold applies to the filtered image, whose noise is the pixel noise times the
    # kernel's root sum of squares: a true matched-filter significance.
    filtered_rms = background.global_rms * float(np.sqrt(np.sum(kernel**2)))
    objects = _extract(
        data,
        threshold * filtered_rms,
        mask=sep_mask,
        minarea=min_area,
        deblend_cont=deblend_contrast,
        filter_kernel=kernel,
        filter_type="conv",
    )
    a, b = np.asarray(objects["a"], np.float64), np.asarray(objects["b"], np.float64)
    fwhm = 2.0 * np.sqrt(math.log(2.0) * (a**2 + b**2))
    x, y = np.asarray(objects["x"], np.float64), np.asarray(objects["y"], np.float64)
    if len(objects) and windowed_centroids:
        # Windowed centroids are far less noisy than isophotal barycentres.
        sigma = np.maximum(fwhm * _SIGMA_PER_FWHM, 0.5)
        x_win, y_win, win_flags = sep.winpos(data, x, y, sigma, mask=sep_mask)
        good = (win_flags == 0) & (np.hypot(x_win - x, y_win - y) < 1.0)
        x, y = np.where(good, x_win, x), np.where(good, y_win, y)
    iy = np.clip(np.rint(y).astype(np.int64), 0, data.shape[0] - 1)
    ix = np.clip(np.rint(x).astype(np.int64), 0, data.shape[1] - 1)
    local_background = background.level[iy, ix]
    peak = np.asarray(objects["peak"], np.float64)
    flags = np.asarray(objects["flag"], np.int32)
    if saturation is not None:
        flags = np.where(peak + local_background >= saturation, flags | FLAG_SATURATED, flags)
    return catalog_table(
        {
            "x": x,
            "y": y,
            "flux": objects["flux"],
            "peak": peak,
            "background": local_background,
            "fwhm": fwhm,
            "ellipticity": 1.0 - b / np.maximum(a, 1e-12),
            "flags": flags,
            "a": a,
            "b": b,
            "theta": objects["theta"],
            "npix": objects["npix"],
        }
    )


#: SEP allocates and initialises its whole pixel stack on every call: 2 M pixels (what crowded
#: 2k x 2k frames may need) cost ~50 ms, most of a seeing measurement on a 512-pixel window. So it
#: starts small and grows when a frame needs more: it bounds the pixels above the threshold being
#: assembled at once, not the result.
_INITIAL_PIXSTACK = 1 << 16
_pixstack_lock = threading.Lock()
_pixstack_set = False


def _extract(data: npt.NDArray[np.float64], threshold: float, **options: Any) -> Any:
    """``sep.extract`` with a pixel stack grown (process-wide, never shrunk) as far as it needs."""
    global _pixstack_set
    with _pixstack_lock:
        if not _pixstack_set:
            sep.set_extract_pixstack(_INITIAL_PIXSTACK)
            _pixstack_set = True
    while True:
        try:
            return sep.extract(data, threshold, **options)
        except Exception as exc:  # SEP raises a bare Exception
            if "pixel buffer full" not in str(exc) or sep.get_extract_pixstack() >= data.size:
                raise _detection_error(exc) from exc
        with _pixstack_lock:
            sep.set_extract_pixstack(min(data.size, 2 * sep.get_extract_pixstack()))


def _detection_error(exc: Exception) -> ImageDataError:
    """SEP's bare exception as one line that names the cause, not SEP's tuning advice."""
    text = str(exc)
    if "deblending overflow" in text:
        return ImageDataError(
            "source detection failed: one blended object holds more sub-objects than SEP keeps "
            "(a very bright star or a crowded field)"
        )
    return ImageDataError(f"source detection failed: {text.split(chr(10))[0]}")


def gaussian_kernel(fwhm: float) -> npt.NDArray[np.float64]:
    """A normalised 2-D Gaussian of ``fwhm`` pixels on a square grid reaching about 1 FWHM."""
    radius = max(1, math.ceil(fwhm))
    offsets = np.arange(-radius, radius + 1, dtype=np.float64)
    sigma = fwhm * _SIGMA_PER_FWHM
    profile = np.exp(-0.5 * (offsets / sigma) ** 2)
    kernel = np.outer(profile, profile)
    return np.asarray(kernel / kernel.sum(), np.float64)


class SepSourceDetection(ImageProcessor):
    """Detect sources with SEP and put them in ``image.catalog`` (the default detector).

    Parameters
    ----------
    threshold
        Detection threshold in sigma of the filtered image's noise (see :func:`detect_sources_sep`).
    min_area
        Minimum connected pixels above the threshold.
    deblend_contrast
        Minimum contrast for deblending.
    box_size
        Background mesh size (pixels).
    kernel_fwhm
        FWHM (pixels) of the Gaussian detection filter; best near the stars' FWHM.
    saturation
        Raw saturation level (data units) if the header has no ``SATURATE``.
    """

    def __init__(
        self,
        *,
        threshold: float = 4.0,
        min_area: int = 5,
        deblend_contrast: float = 0.005,
        box_size: int = 64,
        kernel_fwhm: float = 3.0,
        saturation: float | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        require(threshold > 0, "threshold", f"must be > 0, got {threshold}")
        require(min_area >= 1, "min_area", f"must be >= 1, got {min_area}")
        require(
            0 < deblend_contrast <= 1, "deblend_contrast", f"must be within (0, 1], got {deblend_contrast}"
        )
        require(box_size >= 8, "box_size", f"must be >= 8, got {box_size}")
        require(0 < kernel_fwhm <= 20, "kernel_fwhm", f"must be within (0, 20], got {kernel_fwhm}")
        self.threshold = threshold
        self.min_area = min_area
        self.deblend_contrast = deblend_contrast
        self.box_size = box_size
        self.kernel_fwhm = kernel_fwhm
        self.saturation = saturation

    async def __call__(self, image: Image) -> Image:
        catalog = await asyncio.to_thread(self._blocking_detect, image)
        return image.replace(catalog=catalog)

    def _blocking_detect(self, image: Image) -> Table:
        return detect_sources_sep(
            float_data(image),
            image.mask,
            threshold=self.threshold,
            min_area=self.min_area,
            deblend_contrast=self.deblend_contrast,
            box_size=self.box_size,
            kernel_fwhm=self.kernel_fwhm,
            saturation=saturation_level(image, self.saturation),
        )
