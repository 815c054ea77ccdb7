"""Exposure time from a star field: scale so the brightest unsaturated star peaks at a target."""

from __future__ import annotations

import asyncio
from dataclasses import dataclass
from typing import Any

import numpy as np
from astropy.table import Table  # type: ignore[import-untyped]

from nightcrew.images.errors import ImageError, NoStarsError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require
from nightcrew.images.processors._shared import float_data, saturation_level
from nightcrew.images.processors.detection import FLAG_SATURATED, detect_sources_sep

__all__ = ["EXPOSURE_TIME_KEY", "ExposureTimeEstimate", "StarExposureTime", "star_exposure_time"]

EXPOSURE_TIME_KEY = "exposure_time"


@dataclass(frozen=True)
class ExposureTimeEstimate:
    """Suggested exposure time (s) and the star's peak above background (data units) it used."""

    exposure_time_s: float
    star_peak: float


def star_exposure_time(
    catalog: Table, exposure_time_s: float, *, target_peak: float, saturation: float, bias: float = 0.0
) -> ExposureTimeEstimate:
    """Exposure time making the brightest unsaturated star's peak above background ``target_peak``.

    Star light grows linearly with time, so the time is scaled by ``target_peak / peak``. A star
    counts as saturated if its raw peak (above ``bias``, plus background) reaches 95 % of
    ``saturation - bias``: near the limit, detectors turn non-linear.

    Raises
    ------
    NoStarsError
        No unsaturated star in the catalog.
    """
    peak = np.asarray(catalog["peak"], np.float64)
    raw = peak + np.asarray(catalog["background"], np.float64)
    usable = (np.asarray(catalog["flags"]) & FLAG_SATURATED) == 0
    usable &= (raw - bias < 0.95 * (saturation - bias)) & (peak > 0)
    if not usable.any():
        raise NoStarsError("no unsaturated star to scale the exposure time on")
    brightest = float(peak[usable].max())
    return ExposureTimeEstimate(exposure_time_s * target_peak / brightest, brightest)


class StarExposureTime(ImageProcessor):
    """Estimate the exposure time for a target star peak into ``metadata["exposure_time"]``.

    Parameters
    ----------
    target_peak
        Wanted peak of the brightest star above background (data units, e.g. ADU).
    min_exposure_time, max_exposure_time
        Limits of the suggestion (s).
    saturation
        Saturation level (data units) if the header has no ``SATURATE``.
    bias
        Bias level (data units) included in raw pixels.
    detection_threshold
        Threshold (sigma) when no catalog is present and detection runs here.
    """

    def __init__(
        self,
        *,
        target_peak: float = 30000.0,
        min_exposure_time: float = 0.0,
        max_exposure_time: float = 300.0,
        saturation: float = 65535.0,
        bias: float = 0.0,
        detection_threshold: float = 10.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        require(target_peak > 0, "target_peak", f"must be > 0, got {target_peak}")
        require(
            0 <= min_exposure_time <= max_exposure_time,
            "max_exposure_time",
            f"need 0 <= min_exposure_time <= max_exposure_time, got {min_exposure_time}, {max_exposure_time}",
        )
        self.target_peak = target_peak
        self.min_exposure_time = min_exposure_time
        self.max_exposure_time = max_exposure_time
        self.saturation = saturation
        self.bias = bias
        self.detection_threshold = detection_threshold

    async def __call__(self, image: Image) -> Image:
        exposure_time = image.header.get("EXPTIME")
        if (
            isinstance(exposure_time, bool)
            or not isinstance(exposure_time, int | float)
            or exposure_time <= 0
        ):
            raise ImageError(f"the header needs a positive EXPTIME, got {exposure_time!r}")
        estimate = await asyncio.to_thread(self._blocking_estimate, image, float(exposure_time))
        clipped = min(max(estimate.exposure_time_s, self.min_exposure_time), self.max_exposure_time)
        result = image.copy()
        result.metadata[EXPOSURE_TIME_KEY] = ExposureTimeEstimate(clipped, estimate.star_peak)
        return result

    def _blocking_estimate(self, image: Image, exposure_time: float) -> ExposureTimeEstimate:
        saturation = saturation_level(image, self.saturation)
        assert saturation is not None  # a default is given
        catalog = image.catalog
        if catalog is None:
            catalog = detect_sources_sep(
                float_data(image), image.mask, threshold=self.detection_threshold, saturation=saturation
            )
        return star_exposure_time(
            catalog, exposure_time, target_peak=self.target_peak, saturation=saturation, bias=self.bias
        )
