"""Spectrographs: expose like a camera (same busy, abort, header and file rules), write a spectrum."""

from __future__ import annotations

from abc import abstractmethod
from typing import Any

from nightcrew.events import NewSpectrumEvent
from nightcrew.interfaces import FitsCard, IExposureTime, ISpectrograph
from nightcrew.modules.camera.exposing import ExposingModule, Frame
from nightcrew.timeout import timeout

__all__ = ["BaseSpectrograph"]


class BaseSpectrograph(ExposingModule, ISpectrograph, IExposureTime):
    """A spectrograph; a driver implements :meth:`_hw_expose_spectrum`.

    FITS cards: DATE-OBS, MJD-OBS, EXPTIME, IMAGETYP (``spectrum``) plus peers' and configured ones.

    Args:
        filename_pattern: VFS path of new spectra (default ``/cache/{DATE-OBS}-spectrum.fits``).
        **kwargs: Options of ExposingModule and Module.
    """

    default_pattern = "/cache/{DATE-OBS}-spectrum.fits"

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._exposure_time = 1.0

    @abstractmethod
    async def _hw_expose_spectrum(self, exposure_time: float) -> Frame:
        """Expose and return the spectrum (1-D: flux per pixel, or 2-D raw frame) and driver cards."""

    # As a camera's grab_data: noticed once overdue, not after ISpectrograph's generic hour.
    @timeout(lambda self, **_: self._exposure_timeout(self._exposure_time))
    async def grab_spectrum(self, broadcast: bool = True) -> str:
        self._check_not_busy()
        exposure_time = self._exposure_time

        async def expose() -> Frame:
            return await self._hw_expose_spectrum(exposure_time)

        async def announce(filename: str) -> None:
            await self.comm.send_event(NewSpectrumEvent(filename=filename))

        def own_cards(frame: Frame) -> dict[str, FitsCard]:
            return {"EXPTIME": (exposure_time, "Exposure time [s]"), "IMAGETYP": ("spectrum", "Image type")}

        return await self._take_exposure(expose, exposure_time, own_cards, announce if broadcast else None)

    async def set_exposure_time(self, exposure_time: float) -> None:
        self._exposure_time = self._checked_exposure_time(exposure_time)

    async def get_exposure_time(self) -> float:
        return self._exposure_time

    async def get_exposure_time_left(self) -> float:
        return self._exposure_time_left()
