"""Files the archive makes from stored frames: PNG thumbnails and zip bundles. Blocking: threads."""

from __future__ import annotations

import os
import secrets
import zipfile
from pathlib import Path

import numpy as np
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.images.png import encode_png, stretch_to_uint8

__all__ = ["blocking_thumbnail", "blocking_zip"]


def blocking_thumbnail(frame: Path, cache: Path, size: int) -> bytes:
    """A PNG of the frame's first image, at most ``size`` pixels a side, cached in ``cache``."""
    if cache.exists():
        return cache.read_bytes()
    with fits.open(frame, memmap=False) as hdus:
        data = next((hdu.data for hdu in hdus if hdu.data is not None and np.ndim(hdu.data) >= 2), None)
        if data is None:
            raise ValueError(f"{frame.name} has no image to show")
        png = encode_png(stretch_to_uint8(np.asarray(data, np.float64), max_size=size))
    cache.parent.mkdir(parents=True, exist_ok=True)
    temporary = cache.with_name(f".{cache.name}.{secrets.token_hex(4)}")
    temporary.write_bytes(png)
    os.replace(temporary, cache)  # two requests at once both write the same bytes
    return png


def blocking_zip(files: list[tuple[Path, str]], target: Path) -> None:
    """Write ``(file, name in the zip)`` pairs to ``target`` (stored: FITS hardly compresses)."""
    with zipfile.ZipFile(target, "w", compression=zipfile.ZIP_STORED, allowZip64=True) as bundle:
        for path, name in files:
            bundle.write(path, name)
