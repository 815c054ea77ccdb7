"""Source detection with photutils' DAOStarFinder (Gaussian-kernel peaks of a known FWHM)."""

from __future__ import annotations

import asyncio
from typing import Any

import numpy as np
import numpy.typing as npt
from astropy.table import Table  # type: ignore[import-untyped]

from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require
from nightcrew.images.processors._shared import estimate_background, float_data, saturation_level
from nightcrew.images.processors.detection._catalog import FLAG_SATURATED, catalog_table

__all__ = ["DaoSourceDetection", "detect_sources_dao"]


def detect_sources_dao(
    data: npt.NDArray[np.float64],
    mask: npt.NDArray[np.bool_] | None = None,
    *,
    fwhm: float,
    threshold: float = 5.0,
    box_size: int = 64,
    roundness_limit: float = 1.0,
    saturation: float | None = None,
) -> Table:
    """Stars of about ``fwhm`` pixels in ``data`` (raw pixels; SEP's background is subtracted here).

    ``threshold`` is in sigma of the background noise; ``roundness_limit`` bounds DAOStarFinder's
    roundness statistics (1 is photutils' default). Returns the catalog of :mod:`._catalog`
    plus DAOStarFinder's ``sharpness``, ``roundness1`` and ``roundness2``; ``fwhm`` and
    ``ellipticity`` are not measured (NaN).
    """
    from photutils.detection import DAOStarFinder  # type: ignore[import-untyped]

    background = estimate_background(data, mask, box_size=box_size)
    data -= background.level
    finder = DAOStarFinder(
        threshold=threshold * background.global_rms,
        fwhm=fwhm,
        roundness_range=(-roundness_limit, roundness_limit),
    )
    found = finder(data, mask=mask)
    if found is None or len(found) == 0:
        return catalog_table({"x": np.zeros(0)})
    x, y = np.asarray(found["x_centroid"], np.float64), np.asarray(found["y_centroid"], np.float64)
    iy = np.clip(np.rint(y).astype(np.int64), 0, data.shape[0] - 1)
    ix = np.clip(np.rint(x).astype(np.int64), 0, data.shape[1] - 1)
    local_background = background.level[iy, ix]
    peak = np.asarray(found["peak"], np.float64)
    flags = np.zeros(len(x), np.int32)
    if saturation is not None:
        flags[peak + local_background >= saturation] |= FLAG_SATURATED
    return catalog_table(
        {
            "x": x,
            "y": y,
            "flux": np.asarray(found["flux"], np.float64),
            "peak": peak,
            "background": local_background,
            "flags": flags,
            "sharpness": np.asarray(found["sharpness"], np.float64),
            "roundness1": np.asarray(found["roundness1"], np.float64),
            "roundness2": np.asarray(found["roundness2"], np.float64),
        }
    )


class DaoSourceDetection(ImageProcessor):
    """Detect stars with photutils' DAOStarFinder and put them in ``image.catalog``.

    Parameters
    ----------
    fwhm
        Expected star FWHM (pixels): the size of the detection kernel.
    threshold
        Detection threshold in sigma of the background noise.
    box_size
        Background mesh size (pixels).
    roundness_limit
        Accepted range (±) of the roundness statistics; 1 is photutils' default.
    saturation
        Raw saturation level (data units) if the header has no ``SATURATE``.
    """

    def __init__(
        self,
        *,
        fwhm: float = 3.0,
        threshold: float = 5.0,
        box_size: int = 64,
        roundness_limit: float = 1.0,
        saturation: float | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        require(fwhm > 0, "fwhm", f"must be > 0, got {fwhm}")
        require(threshold > 0, "threshold", f"must be > 0, got {threshold}")
        require(box_size >= 8, "box_size", f"must be >= 8, got {box_size}")
        self.fwhm = fwhm
        self.threshold = threshold
        self.box_size = box_size
        self.roundness_limit = roundness_limit
        self.saturation = saturation

    async def __call__(self, image: Image) -> Image:
        catalog = await asyncio.to_thread(self._blocking_detect, image)
        return image.replace(catalog=catalog)

    def _blocking_detect(self, image: Image) -> Table:
        return detect_sources_dao(
            float_data(image),
            image.mask,
            fwhm=self.fwhm,
            threshold=self.threshold,
            box_size=self.box_size,
            roundness_limit=self.roundness_limit,
            saturation=saturation_level(image, self.saturation),
        )
