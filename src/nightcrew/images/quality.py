"""How good a frame is, from its pixels alone: star FWHM, ellipticity, star count, sky background.

The stars are SEP's (:func:`~nightcrew.images.processors.detection.detect_sources_sep`): the
unflagged ones (not saturated, blended or cut by the edge) whose peak stands ``min_peak_snr``
times above the background noise. FWHM and ellipticity (``1 - b/a``) are their medians, from SEP's
own moments - no profile fits, so a 2k frame takes a fraction of a second. The sky is the median of
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
    image: Image, *, threshold: float = 5.0, min_peak_snr: float = 10.0
) -> FrameQuality:
    """The quality of ``image`` (blocking: a fraction of a second for a 2k frame; call it in a thread).

    Raises:
        ImageDataError: The frame is too small for a background, or wholly masked.
    """
    data, mask = float_data(image), image.mask
    background = estimate_background(data, mask)
    catalog = detect_sources_sep(
        data, mask, threshold=threshold, saturation=saturation_level(image, None), windowed_centroids=False
    )
    peak = np.asarray(catalog["peak"], np.float64)
    fwhm = np.asarray(catalog["fwhm"], np.float64)
    ellipticity = np.asarray(catalog["ellipticity"], np.float64)
    good = (np.asarray(catalog["flags"]) == 0) & (peak >= min_peak_snr * background.global_rms)
    good &= np.isfinite(fwhm) & np.isfinite(ellipticity)
    scale = image.pixel_scale or 1.0
    count = int(good.sum())
    return FrameQuality(
        fwhm=float(np.median(fwhm[good])) * scale if count else math.nan,
        ellipticity=float(np.median(ellipticity[good])) if count else math.nan,
        stars=count,
        sky=float(np.median(background.level)),
    )
