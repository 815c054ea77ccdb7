"""Errors of images and image processors, all under :class:`nightcrew.errors.NightcrewError`::

    NightcrewError
    └── ImageError              anything wrong with an image or its processing
        ├── ImageDataError      pixel data of the wrong kind: not 2-D, empty, bool/complex dtype,
        │                       arrays of different shapes
        ├── ImageFormatError    bytes that are not a FITS image, or an image that cannot be written
        ├── MissingWcsError     a WCS (or pixel scale) is needed but the header has none
        └── NoStarsError        too few usable stars for the measurement

Class names are unique in nightcrew, so errors keep their class across RPC.
"""

from __future__ import annotations

from nightcrew.errors import NightcrewError

__all__ = ["ImageDataError", "ImageError", "ImageFormatError", "MissingWcsError", "NoStarsError"]


class ImageError(NightcrewError):
    """Base of all image errors."""


class ImageDataError(ImageError):
    """Pixel data of the wrong kind (dimensions, dtype, size or mismatched shapes)."""


class ImageFormatError(ImageError):
    """Bytes that cannot be read as, or an image that cannot be written to, FITS."""


class MissingWcsError(ImageError):
    """The image has no celestial WCS (or pixel scale), but the operation needs one."""


class NoStarsError(ImageError):
    """Too few usable stars in the image for the measurement."""
