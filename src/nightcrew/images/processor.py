"""The base of image processors: ``await processor(image)`` returns a new image.

A processor is configured in its constructor (typed keyword arguments, so it can be described in
YAML as ``{class: nightcrew.images.processors.detection.SepSourceDetection, threshold: 3}``), never
changes the image it is given (see :class:`~nightcrew.images.Image`), and runs its numeric work in
a worker thread (``asyncio.to_thread`` on a ``_blocking_*`` method or a pure function), so a
guiding loop's event loop stays responsive. Processors derive from :class:`~nightcrew.object.Object`
to receive the VFS (e.g. to read a mask file) when added as a child of a module or pipeline.
"""

from __future__ import annotations

import abc
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.images.image import Image
from nightcrew.object import Object

__all__ = ["ImageProcessor", "require"]


class ImageProcessor(Object, abc.ABC):
    """Base class of all image processors.

    Parameters
    ----------
    **kwargs
        Context for :class:`~nightcrew.object.Object` (``vfs``, ``comm``, ...).
    """

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)

    @abc.abstractmethod
    async def __call__(self, image: Image) -> Image:
        """Process ``image`` and return the result (a new image; ``image`` is left unchanged)."""

    async def reset(self) -> None:
        """Forget state kept between images (e.g. an offsets reference); stateless: nothing."""


def require(condition: bool, key: str, message: str) -> None:
    """Raise :class:`ConfigError` for constructor argument ``key`` unless ``condition`` holds."""
    if not condition:
        raise ConfigError(message, key=key)
