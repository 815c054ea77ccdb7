"""Aperture photometry with SEP and with photutils."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
import sep  # type: ignore[import-not-found]

from nightcrew.images.processors._shared import Background
from nightcrew.images.processors.photometry._apertures import AperturePhotometry

__all__ = ["PhotutilsPhotometry", "SepPhotometry"]

FloatArray = npt.NDArray[np.float64]


class SepPhotometry(AperturePhotometry):
    """Circular apertures with SEP's exact pixel overlap (``sep.sum_circle``)."""

    def _measure(
        self,
        data: FloatArray,
        mask: npt.NDArray[np.bool_] | None,
        background: Background,
        x: FloatArray,
        y: FloatArray,
        radius: float,
    ) -> tuple[FloatArray, FloatArray]:
        sep_mask = None if mask is None else np.ascontiguousarray(mask, dtype=np.uint8)
        flux, error, _ = sep.sum_circle(data, x, y, radius, err=background.rms, mask=sep_mask, subpix=0)
        return np.asarray(flux, np.float64), np.asarray(error, np.float64)


class PhotutilsPhotometry(AperturePhotometry):
    """Circular apertures with photutils' ``aperture_photometry`` (exact overlap)."""

    def _measure(
        self,
        data: FloatArray,
        mask: npt.NDArray[np.bool_] | None,
        background: Background,
        x: FloatArray,
        y: FloatArray,
        radius: float,
    ) -> tuple[FloatArray, FloatArray]:
        from photutils.aperture import CircularAperture, aperture_photometry  # type: ignore[import-untyped]

        apertures = CircularAperture(np.column_stack([x, y]), r=radius)
        table = aperture_photometry(data, apertures, error=background.rms, mask=mask, method="exact")
        return (
            np.asarray(table["aperture_sum"], np.float64),
            np.asarray(table["aperture_sum_err"], np.float64),
        )
