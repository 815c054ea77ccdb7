"""Spectrographs: the base class for their drivers."""

from nightcrew.modules.spectrograph.base import BaseSpectrograph

__all__ = ["BaseSpectrograph"]
