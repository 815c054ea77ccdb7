"""Aperture photometry shared parts: radii in pixels, column names, catalog checks."""

from __future__ import annotations

import abc
import asyncio
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import numpy.typing as npt
from astropy.table import Table  # type: ignore[import-untyped]

from nightcrew.images.errors import ImageError, MissingWcsError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require
from nightcrew.images.processors._shared import Background, estimate_background, float_data

__all__ = ["AperturePhotometry", "flux_columns"]

FloatArray = npt.NDArray[np.float64]


def flux_columns(index: int) -> tuple[str, str]:
    """Names of the flux and flux-error columns of aperture ``index`` (1-based)."""
    return f"aperflux{index}", f"aperfluxerr{index}"


class AperturePhotometry(ImageProcessor, abc.ABC):
    """Base of aperture photometry on the catalog's positions (background subtracted first).

    Adds columns ``aperflux<i>`` and ``aperfluxerr<i>`` per aperture (data units) and records each
    radius in pixels in the catalog's meta (``APER<i>``).

    Parameters
    ----------
    radii
        Aperture radii.
    unit
        ``arcsec`` (needs a pixel scale) or ``px``.
    """

    def __init__(
        self, *, radii: Sequence[float] = (3.0,), unit: Literal["arcsec", "px"] = "px", **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        require(len(radii) >= 1 and all(r > 0 for r in radii), "radii", f"must be positive, got {radii!r}")
        require(unit in ("arcsec", "px"), "unit", f"must be arcsec or px, got {unit!r}")
        self.radii = tuple(float(r) for r in radii)
        self.unit = unit

    async def __call__(self, image: Image) -> Image:
        if image.catalog is None:
            raise ImageError("aperture photometry needs a catalog: run a detection step first")
        radii_px = self.radii
        if self.unit == "arcsec":
            scale = image.pixel_scale
            if scale is None:
                raise MissingWcsError("radii in arcsec need a pixel scale (WCS or PIXSCALE)")
            radii_px = tuple(r / scale for r in radii_px)
        catalog = await asyncio.to_thread(self._blocking_photometry, image, image.catalog, radii_px)
        return image.replace(catalog=catalog)

    def _blocking_photometry(self, image: Image, catalog: Table, radii_px: tuple[float, ...]) -> Table:
        data = float_data(image)
        background = estimate_background(data, image.mask)
        data -= background.level
        x, y = np.asarray(catalog["x"], np.float64), np.asarray(catalog["y"], np.float64)
        result = catalog.copy()
        for index, radius in enumerate(radii_px, start=1):
            flux, error = self._measure(data, image.mask, background, x, y, radius)
            flux_name, error_name = flux_columns(index)
            result[flux_name], result[error_name] = flux, error
            result.meta[f"APER{index}"] = radius
        return result

    @abc.abstractmethod
    def _measure(
        self,
        data: FloatArray,
        mask: npt.NDArray[np.bool_] | None,
        background: Background,
        x: FloatArray,
        y: FloatArray,
        radius: float,
    ) -> tuple[FloatArray, FloatArray]:
        """Fluxes and 1-sigma errors in circles of ``radius`` px on background-free ``data``."""
