"""Offsets against a fixed position, no reference needed: brightest star, header keywords, WCS."""

from __future__ import annotations

import asyncio
from collections.abc import Sequence
from typing import Any

import numpy as np

from nightcrew.images.errors import ImageError, MissingWcsError, NoStarsError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require
from nightcrew.images.processors._shared import float_data, saturation_level
from nightcrew.images.processors.detection import detect_sources_sep
from nightcrew.images.processors.offsets._result import with_offsets

__all__ = ["AstrometryOffsets", "BrightestStarOffsets", "FitsHeaderOffsets"]


def _centre(image: Image, position: Sequence[float] | None) -> tuple[float, float]:
    rows, cols = image.shape
    if position is None:
        return (cols - 1) / 2.0, (rows - 1) / 2.0
    return float(position[0]), float(position[1])


def _pair(value: Sequence[Any] | None, key: str, kind: type) -> None:
    require(
        value is None or (len(value) == 2 and all(isinstance(v, kind) for v in value)),
        key,
        f"must be two {kind.__name__} values, got {value!r}",
    )


class BrightestStarOffsets(ImageProcessor):
    """Offsets of the brightest unflagged star from a target pixel (the image centre by default).

    Uses the image's catalog if present, else SEP detection.

    Parameters
    ----------
    target
        (x, y) 0-based pixel where the star should be; None for the image centre.
    detection_threshold
        Threshold (sigma) when detecting here.
    """

    def __init__(
        self, *, target: Sequence[float] | None = None, detection_threshold: float = 10.0, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        _pair(target, "target", float)
        require(detection_threshold > 0, "detection_threshold", f"must be > 0, got {detection_threshold}")
        self.target = None if target is None else (float(target[0]), float(target[1]))
        self.detection_threshold = detection_threshold

    async def __call__(self, image: Image) -> Image:
        x, y = await asyncio.to_thread(self._blocking_brightest, image)
        cx, cy = _centre(image, self.target)
        return with_offsets(image, x - cx, y - cy, type(self).__name__)

    def _blocking_brightest(self, image: Image) -> tuple[float, float]:
        catalog = image.catalog
        if catalog is None:
            catalog = detect_sources_sep(
                float_data(image),
                image.mask,
                threshold=self.detection_threshold,
                saturation=saturation_level(image, None),
            )
        usable = np.flatnonzero(np.asarray(catalog["flags"]) == 0)
        if len(usable) == 0:
            raise NoStarsError("no unflagged star on the image")
        best = usable[int(np.argmax(np.asarray(catalog["flux"], np.float64)[usable]))]
        return float(catalog["x"][best]), float(catalog["y"][best])


class FitsHeaderOffsets(ImageProcessor):
    """Offsets between two pixel positions written in the header: target minus centre.

    Parameters
    ----------
    target
        Keywords (x, y) of where the object is, e.g. written by an acquisition step.
    centre
        Keywords (x, y) of where it should be (the same pixel convention as ``target``).
    """

    def __init__(
        self,
        *,
        target: Sequence[str] = ("TARGETX", "TARGETY"),
        centre: Sequence[str] = ("CRPIX1", "CRPIX2"),
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        _pair(target, "target", str)
        _pair(centre, "centre", str)
        self.target = (target[0], target[1])
        self.centre = (centre[0], centre[1])

    async def __call__(self, image: Image) -> Image:
        values: list[float] = []
        for keyword in (*self.target, *self.centre):
            value = image.header.get(keyword)
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ImageError(f"header keyword {keyword} is missing or not a number: {value!r}")
            values.append(float(value))
        tx, ty, cx, cy = values
        return with_offsets(image, tx - cx, ty - cy, type(self).__name__)


class AstrometryOffsets(ImageProcessor):
    """Offsets of the requested sky position from a target pixel, through the image's WCS.

    The WCS must describe the real sky (e.g. written by a plate solver); the requested position
    comes from header keywords (the telescope's RA/Dec in degrees by default).

    Parameters
    ----------
    position_keywords
        Keywords (RA, Dec) of the requested position, degrees.
    target
        (x, y) 0-based pixel where the requested position should fall; None for the centre.
    """

    def __init__(
        self,
        *,
        position_keywords: Sequence[str] = ("RA", "DEC"),
        target: Sequence[float] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        _pair(position_keywords, "position_keywords", str)
        _pair(target, "target", float)
        self.position_keywords = (position_keywords[0], position_keywords[1])
        self.target = None if target is None else (float(target[0]), float(target[1]))

    async def __call__(self, image: Image) -> Image:
        if image.wcs is None:
            raise MissingWcsError("AstrometryOffsets needs a WCS (plate-solve the image first)")
        ra, dec = (image.header.get(k) for k in self.position_keywords)
        if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in (ra, dec)):
            raise ImageError(f"header keywords {self.position_keywords} must hold the requested RA/Dec")
        x, y = image.sky_to_pixel(float(ra), float(dec))
        cx, cy = _centre(image, self.target)
        return with_offsets(image, float(x) - cx, float(y) - cy, type(self).__name__)
