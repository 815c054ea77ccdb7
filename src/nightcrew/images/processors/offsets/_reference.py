"""Offsets relative to a reference image: the first image (after a reset) becomes the reference.

The reference is dropped on :meth:`ReferenceOffsets.reset`, and automatically when an image
differs from it in shape or in one of the ``reset_keywords`` (by default the target name and
binning: a new target or readout needs a new reference).
"""

from __future__ import annotations

import abc
import asyncio
from collections.abc import Sequence
from typing import Any, Generic, TypeVar

from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor
from nightcrew.images.processors.offsets._result import with_offsets

__all__ = ["ReferenceOffsets"]

R = TypeVar("R")

DEFAULT_RESET_KEYWORDS = ("OBJECT", "XBINNING", "YBINNING")


class ReferenceOffsets(ImageProcessor, abc.ABC, Generic[R]):
    """Base of offsets measured against a reference; subclasses say what they keep and compare.

    Parameters
    ----------
    reset_keywords
        Header keywords whose change starts a new reference.
    **kwargs
        Context for :class:`~nightcrew.object.Object`.
    """

    def __init__(self, *, reset_keywords: Sequence[str] = DEFAULT_RESET_KEYWORDS, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.reset_keywords = tuple(reset_keywords)
        self._reference: R | None = None
        self._reference_key: tuple[Any, ...] | None = None

    async def __call__(self, image: Image) -> Image:
        key = (image.shape, *(image.header.get(k) for k in self.reset_keywords))
        if self._reference is None or key != self._reference_key:
            self._reference = await asyncio.to_thread(self._blocking_reference, image)
            self._reference_key = key
            return with_offsets(image, 0.0, 0.0, type(self).__name__, is_reference=True)
        dx, dy = await asyncio.to_thread(self._blocking_offsets, self._reference, image)
        return with_offsets(image, dx, dy, type(self).__name__)

    async def reset(self) -> None:
        """Forget the reference: the next image becomes the new one."""
        self._reference = None
        self._reference_key = None

    @abc.abstractmethod
    def _blocking_reference(self, image: Image) -> R:
        """What to keep of the reference image (runs in a worker thread)."""

    @abc.abstractmethod
    def _blocking_offsets(self, reference: R, image: Image) -> tuple[float, float]:
        """Pixel offsets (dx, dy) of ``image`` against ``reference`` (runs in a worker thread)."""
