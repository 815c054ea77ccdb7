"""Pixel operations: background removal, soft binning, flips, normalisation, masks."""

from __future__ import annotations

import asyncio
from typing import Any, Literal

import numpy as np
import numpy.typing as npt

from nightcrew.images.errors import ImageDataError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require
from nightcrew.images.processors._shared import estimate_background, float_data

__all__ = ["Flip", "Mask", "Normalise", "RemoveBackground", "SoftBin", "soft_bin"]

FloatArray = npt.NDArray[np.float64]


class RemoveBackground(ImageProcessor):
    """Subtract SEP's mesh background; data become float32.

    Parameters
    ----------
    box_size
        Background mesh size (pixels); several times the largest star.
    """

    def __init__(self, *, box_size: int = 64, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        require(box_size >= 8, "box_size", f"must be >= 8, got {box_size}")
        self.box_size = box_size

    async def __call__(self, image: Image) -> Image:
        return await asyncio.to_thread(self._blocking_remove, image)

    def _blocking_remove(self, image: Image) -> Image:
        data = float_data(image)
        data -= estimate_background(data, image.mask, box_size=self.box_size).level
        return image.replace(data=data.astype(np.float32))


def soft_bin(data: FloatArray, factor: int) -> FloatArray:
    """Sum of ``factor`` x ``factor`` pixel blocks; rows/columns beyond a whole block are dropped."""
    rows, cols = (s // factor for s in data.shape)
    if rows == 0 or cols == 0:
        raise ImageDataError(f"a {data.shape} frame is smaller than one {factor}x{factor} block")
    blocks = data[: rows * factor, : cols * factor].reshape(rows, factor, cols, factor)
    return np.asarray(blocks.sum(axis=(1, 3)), np.float64)


class SoftBin(ImageProcessor):
    """Bin in software: sums of blocks (a bad pixel spoils its block); WCS and catalog follow.

    Parameters
    ----------
    factor
        Block size (pixels per side).
    """

    def __init__(self, *, factor: int = 2, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        require(factor >= 1, "factor", f"must be >= 1, got {factor}")
        self.factor = factor

    async def __call__(self, image: Image) -> Image:
        return await asyncio.to_thread(self._blocking_bin, image)

    def _blocking_bin(self, image: Image) -> Image:
        f = self.factor
        data = soft_bin(np.asarray(image.data, np.float64), f)
        mask = None if image.mask is None else soft_bin(image.mask.astype(np.float64), f) > 0
        uncertainty = (
            None
            if image.uncertainty is None
            else np.sqrt(soft_bin(np.asarray(image.uncertainty, np.float64) ** 2, f))
        )
        header = image.header.copy()
        # Pixel centre u (0-based, unbinned) lands on (u - (f - 1) / 2) / f; FITS pixels are 1-based.
        for axis in (1, 2):
            if f"CRPIX{axis}" in header:
                header[f"CRPIX{axis}"] = (header[f"CRPIX{axis}"] - 1 - (f - 1) / 2) / f + 1
            for other in (1, 2):
                if f"CD{other}_{axis}" in header:
                    header[f"CD{other}_{axis}"] = header[f"CD{other}_{axis}"] * f
            if f"CDELT{axis}" in header:
                header[f"CDELT{axis}"] = header[f"CDELT{axis}"] * f
        for keyword in ("XBINNING", "YBINNING"):
            header[keyword] = int(header.get(keyword, 1)) * f
        for keyword in ("PIXSCALE", "XPIXSZ", "YPIXSZ"):
            if keyword in header:
                header[keyword] = header[keyword] * f
        catalog = None
        if image.catalog is not None:
            catalog = image.catalog.copy()
            catalog["x"] = (catalog["x"] - (f - 1) / 2) / f
            catalog["y"] = (catalog["y"] - (f - 1) / 2) / f
        return image.replace(data=data, mask=mask, uncertainty=uncertainty, header=header, catalog=catalog)


class Flip(ImageProcessor):
    """Mirror the image along x (columns) and/or y (rows); WCS and catalog follow.

    Parameters
    ----------
    flip_x
        Mirror left-right.
    flip_y
        Mirror top-bottom.
    """

    def __init__(self, *, flip_x: bool = False, flip_y: bool = False, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.flip_x = flip_x
        self.flip_y = flip_y

    async def __call__(self, image: Image) -> Image:
        rows, cols = image.shape
        index = (slice(None, None, -1 if self.flip_y else 1), slice(None, None, -1 if self.flip_x else 1))
        header = image.header.copy()
        catalog = None if image.catalog is None else image.catalog.copy()
        for flipped, axis, size, column in ((self.flip_x, 1, cols, "x"), (self.flip_y, 2, rows, "y")):
            if not flipped:
                continue
            if f"CRPIX{axis}" in header:
                header[f"CRPIX{axis}"] = size + 1 - header[f"CRPIX{axis}"]
            for other in (1, 2):
                if f"CD{other}_{axis}" in header:
                    header[f"CD{other}_{axis}"] = -header[f"CD{other}_{axis}"]
            if f"CDELT{axis}" in header:
                header[f"CDELT{axis}"] = -header[f"CDELT{axis}"]
            if catalog is not None:
                catalog[column] = size - 1 - catalog[column]
        return image.replace(
            data=image.data[index],
            mask=None if image.mask is None else image.mask[index],
            uncertainty=None if image.uncertainty is None else image.uncertainty[index],
            header=header,
            catalog=catalog,
        )


class Normalise(ImageProcessor):
    """Divide by the median or mean of the good pixels (e.g. flat fields to 1); float data.

    Parameters
    ----------
    statistic
        ``median`` (robust against stars and defects) or ``mean``.
    """

    def __init__(self, *, statistic: Literal["median", "mean"] = "median", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        require(statistic in ("median", "mean"), "statistic", f"must be median or mean, got {statistic!r}")
        self.statistic = statistic

    async def __call__(self, image: Image) -> Image:
        return await asyncio.to_thread(self._blocking_normalise, image)

    def _blocking_normalise(self, image: Image) -> Image:
        data = np.asarray(image.data, np.float64)
        good = data if image.mask is None else data[~image.mask]
        level = float(np.median(good) if self.statistic == "median" else np.mean(good))
        if not np.isfinite(level) or level == 0:
            raise ImageDataError(f"cannot normalise: the {self.statistic} of the good pixels is {level}")
        uncertainty = None if image.uncertainty is None else image.uncertainty / abs(level)
        result = image.replace(data=data / level, uncertainty=uncertainty)
        result.header["NORMLEVL"] = (level, f"Data were divided by this {self.statistic}")
        return result


class Mask(ImageProcessor):
    """Mark bad pixels from a boolean array or a FITS file on the VFS (nonzero = bad).

    The given mask is combined (logical or) with the image's own. A file is read on first use.

    Parameters
    ----------
    path
        VFS path of a FITS image (first image HDU) whose nonzero pixels are bad.
    mask
        The bad pixels as a boolean array (in code, instead of ``path``).
    """

    def __init__(
        self, *, path: str | None = None, mask: npt.NDArray[np.bool_] | None = None, **kwargs: Any
    ) -> None:
        super().__init__(**kwargs)
        require((path is None) != (mask is None), "path", "give exactly one of path and mask")
        self.path = path
        self._mask = None if mask is None else np.asarray(mask, bool)

    async def __call__(self, image: Image) -> Image:
        if self._mask is None:
            assert self.path is not None  # the constructor requires one of them
            self._mask = np.asarray((await Image.from_vfs(self.vfs, self.path)).data) != 0
        if self._mask.shape != image.shape:
            raise ImageDataError(f"mask has shape {self._mask.shape}, but the image has {image.shape}")
        combined = self._mask if image.mask is None else self._mask | image.mask
        return image.replace(mask=combined)
