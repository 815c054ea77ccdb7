"""Modules that work on images other modules took."""

from nightcrew.modules.image.seeing import Seeing

__all__ = ["Seeing"]
