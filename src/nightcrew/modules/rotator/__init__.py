"""Field rotators: the base class for their drivers."""

from nightcrew.modules.rotator.base import BaseRotator

__all__ = ["BaseRotator"]
