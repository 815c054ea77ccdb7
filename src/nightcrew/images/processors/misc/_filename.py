"""File names from header keywords, with the camera's pattern rules (one implementation)."""

from __future__ import annotations

import posixpath
from typing import Any

from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor
from nightcrew.vfs.filenames import check_filename_pattern, format_filename

__all__ = ["FILENAME_KEY", "CreateFilename"]

FILENAME_KEY = "filename"


class CreateFilename(ImageProcessor):
    """Name the image from its header: ``metadata["filename"]`` (VFS path) and ``FNAME`` (base name).

    Parameters
    ----------
    pattern
        An absolute VFS path with ``{KEYWORD}`` placeholders, as for cameras, e.g.
        ``/archive/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits``; checked when built.
    """

    def __init__(self, *, pattern: str, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        check_filename_pattern(pattern, key="pattern")
        self.pattern = pattern

    async def __call__(self, image: Image) -> Image:
        path = format_filename(self.pattern, image.header)
        result = image.copy()
        result.metadata[FILENAME_KEY] = path
        result.header["FNAME"] = (posixpath.basename(path)[:68], "File name")
        return result
