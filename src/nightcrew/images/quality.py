"""How good a frame is, from its pixels alone: star FWHM, ellipticity, star count, sky background.

The stars are SEP's (:func:`~nightcrew.images.processors.detection.detect_sources_sep`): the
unflagged ones (not saturated, blended or cut by the edge) whose peak stands ``min_peak_snr``
times above the background noise. The FWHM is the median of Moffat fits to the brightest
``max_stars`` of them (:func:`~nightcrew.images.processors.misc.measure_fwhm`, as the seeing
monitor measures it; SEP's isophotal moments miss the wings), the ellipticity (``1 - b/a``) the
median of SEP's moments. The sky is the median of
the background model, in data units (bias included in a raw frame: grading compares frames of one
setup, so of one exposure time).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nightcrew.images.image import Image
from nightcrew.images.processors._shared import estimate_background, float_data, saturation_level
from nightcrew.images.processors.detection import detect_sources_sep
from nightcrew.images.processors.misc import measure_fwhm

__all__ = ["FrameQuality", "measure_frame_quality"]


@dataclass(frozen=True)
class FrameQuality:
    """What grading looks at. ``fwhm`` and ``ellipticity`` are NaN when no star was good enough.

    Attributes:
        fwhm: Median star FWHM, arcsec when the frame has a pixel scale, else pixels.
        ellipticity: Median ``1 - b/a`` of the stars (0: round).
        stars: Number of good stars.
        sky: Median sky level, data units.
    """

    fwhm: float
    ellipticity: float
    stars: int
    sky: float


def measure_frame_quality(
    image: Image,
    *,
    threshold: float = 5.0,
    min_peak_snr: float = 10.0,
    max_stars: int = 30,
    half_size: int = 8,
) -> FrameQuality:
    """The quality of ``image`` (blocking: a fraction of a second for a 2k frame; call it in a thread).

    Raises:
        ImageDataError: The frame is too small for a background, or wholly masked.
    """
    data, mask = float_data(image), image.mask
    background = estimate_background(data, mask)
    catalog = detect_sources_sep(
        data.copy(),
        mask,
        threshold=threshold,
        saturation=saturation_level(image, None),
        windowed_centroids=False,
    )
    peak = np.asarray(catalog["peak"], np.float64)
    ellipticity = np.asarray(catalog["ellipticity"], np.float64)
    good = (np.asarray(catalog["flags"]) == 0) & (peak >= min_peak_snr * background.global_rms)
    good &= np.isfinite(ellipticity)
    count = int(good.sum())
    brightest = np.flatnonzero(good)[np.argsort(-peak[good], kind="stable")][:max_stars]
    x, y = np.asarray(catalog["x"], np.float64), np.asarray(catalog["y"], np.float64)
    fitted = measure_fwhm(data - background.level, x[brightest], y[brightest], half_size=half_size)
    fitted = fitted[np.isfinite(fitted)]
    return FrameQuality(
        fwhm=float(np.median(fitted)) * (image.pixel_scale or 1.0) if len(fitted) else math.nan,
        ellipticity=float(np.median(ellipticity[good])) if count else math.nan,
        stars=count,
        sky=float(np.median(background.level)),
    )
