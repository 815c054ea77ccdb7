"""Images and image processing: the :class:`Image` and the processors that work on it.

An :class:`Image` holds pixels, FITS header, bad-pixel mask, uncertainty, source catalog and
metadata, and reads/writes multi-extension FITS (bytes or VFS paths). Image errors derive from
:class:`ImageError` (see :mod:`nightcrew.images.errors`). This package imports astropy; core
modules must not import it.
"""

from nightcrew.images.errors import (
    ImageDataError,
    ImageError,
    ImageFormatError,
    MissingWcsError,
    NoStarsError,
)
from nightcrew.images.image import Image

__all__ = [
    "Image",
    "ImageDataError",
    "ImageError",
    "ImageFormatError",
    "MissingWcsError",
    "NoStarsError",
]
