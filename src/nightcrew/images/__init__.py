"""Images and image processing: the :class:`Image` and the processors that work on it.

An :class:`Image` holds pixels, FITS header, bad-pixel mask, uncertainty, source catalog and
metadata, and reads/writes multi-extension FITS (bytes or VFS paths). An :class:`ImageProcessor`
returns a new image (``await processor(image)``); a :class:`Pipeline` chains them. Processors live
in :mod:`nightcrew.images.processors` (detection, photometry, offsets, exptime, misc). Image
errors derive from :class:`ImageError` (see :mod:`nightcrew.images.errors`). This package imports
astropy; core modules must not import it.
"""

from nightcrew.images.errors import (
    ImageDataError,
    ImageError,
    ImageFormatError,
    MissingWcsError,
    NoStarsError,
)
from nightcrew.images.image import Image
from nightcrew.images.pipeline import Pipeline
from nightcrew.images.processor import ImageProcessor

__all__ = [
    "Image",
    "ImageDataError",
    "ImageError",
    "ImageFormatError",
    "ImageProcessor",
    "MissingWcsError",
    "NoStarsError",
    "Pipeline",
]
