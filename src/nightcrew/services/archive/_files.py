"""Files the archive makes from stored frames: PNG thumbnails and zip bundles. Blocking: threads."""

from __future__ import annotations

import os
import secrets
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.images.png import encode_png, stretch_to_uint8
from nightcrew.services.archive._fits import declared_pixels

__all__ = ["blocking_thumbnail", "blocking_zip"]


#: Longest side of the pixels a thumbnail reads: larger images are read every n-th pixel, so a
#: thumbnail never holds more than this squared (as float64: 32 MiB) whatever the frame's size.
THUMBNAIL_SOURCE_SIDE = 2048
#: Pixels read at a time (2 MiB as float64).
_READ_PIXELS = 2**18


def blocking_thumbnail(frame: Path, cache: Path, size: int, max_pixels: int) -> bytes:
    """A PNG of the frame's first image, at most ``size`` pixels a side, cached in ``cache``.

    Raises ValueError when the frame has no image or declares more than ``max_pixels`` pixels.
    """
    if cache.exists():
        return cache.read_bytes()
    with fits.open(frame, memmap=False) as hdus:
        hdu = next((hdu for hdu in hdus if declared_pixels(hdu) and len(hdu.shape) >= 2), None)
        if hdu is None:
            raise ValueError(f"{frame.name} has no image to show")
        if declared_pixels(hdu) > max_pixels:
            raise ValueError(f"{frame.name} declares {declared_pixels(hdu)} pixels, more than {max_pixels}")
        png = encode_png(stretch_to_uint8(_sampled(hdu), max_size=size))
    cache.parent.mkdir(parents=True, exist_ok=True)
    temporary = cache.with_name(f".{cache.name}.{secrets.token_hex(4)}")
    temporary.write_bytes(png)
    os.replace(temporary, cache)  # two requests at once both write the same bytes
    return png


def _sampled(hdu: Any) -> npt.NDArray[np.float64]:
    """The first plane of an image HDU, every n-th pixel so that no side exceeds the source side.

    Read through ``section`` (only the rows needed, tile by tile when compressed) in blocks of at
    most :data:`_READ_PIXELS` pixels; astropy reads a column step pixel by pixel, so columns are
    thinned after each block is read.
    """
    rows, cols = hdu.shape[-2:]
    step = max(1, -(-max(rows, cols) // THUMBNAIL_SOURCE_SIDE))
    plane = (0,) * (len(hdu.shape) - 2)
    block = step * max(1, _READ_PIXELS // cols)
    sampled = np.empty((-(-rows // step), -(-cols // step)), np.float64)
    for start in range(0, rows, block):
        part = hdu.section[(*plane, slice(start, min(start + block, rows), step))]
        sampled[start // step : start // step + len(part)] = part[:, ::step]
    return sampled


def blocking_zip(files: list[tuple[Path, str]], target: Path) -> None:
    """Write ``(file, name in the zip)`` pairs to ``target`` (stored: FITS hardly compresses)."""
    with zipfile.ZipFile(target, "w", compression=zipfile.ZIP_STORED, allowZip64=True) as bundle:
        for path, name in files:
            bundle.write(path, name)
