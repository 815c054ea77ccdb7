"""A pipeline: processors applied one after the other, itself a processor.

From YAML::

    class: nightcrew.images.Pipeline
    steps:
      - class: nightcrew.images.processors.misc.RemoveBackground
      - class: nightcrew.images.processors.detection.SepSourceDetection
        threshold: 3.0
      - class: nightcrew.images.processors.offsets.NStarOffsets
        stars: 10
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor

__all__ = ["Pipeline"]


class Pipeline(ImageProcessor):
    """Processors run in order; each receives the previous one's result.

    Parameters
    ----------
    steps
        Processors, or their descriptions (mappings with ``class``), built here.
    **kwargs
        Context for :class:`~nightcrew.object.Object`; passed on to the steps.
    """

    def __init__(self, steps: Sequence[ImageProcessor | Mapping[str, Any]], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.steps: list[ImageProcessor] = [
            self.add_child(_built(step, f"steps.{index}")) for index, step in enumerate(steps)
        ]

    async def __call__(self, image: Image) -> Image:
        for step in self.steps:
            image = await step(image)
        return image

    async def reset(self) -> None:
        """Reset every step."""
        for step in self.steps:
            await step.reset()


def _built(step: ImageProcessor | Mapping[str, Any], key: str) -> ImageProcessor:
    if isinstance(step, ImageProcessor):
        return step
    if not isinstance(step, Mapping):
        raise ConfigError(f"expected an image processor or its description, got {step!r}", key=key)
    built = build_object(step, ImageProcessor)
    assert isinstance(built, ImageProcessor)  # build_object checked the class
    return built
