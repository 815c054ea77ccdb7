"""Spectrographs: like a camera, but what they produce is a spectrum."""

from __future__ import annotations

from abc import abstractmethod

from nightcrew.interfaces.camera import IExposure
from nightcrew.interfaces.control import IAbortable
from nightcrew.timeout import timeout

__all__ = ["ISpectrograph"]


class ISpectrograph(IAbortable, IExposure):
    """A spectrograph: takes spectra, can be aborted and watched."""

    @timeout(3600)
    @abstractmethod
    async def grab_spectrum(self, broadcast: bool = True) -> str:
        """Take one spectrum and return its VFS path; broadcast a NewSpectrumEvent if asked."""
