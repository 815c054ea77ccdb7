"""Cameras and what can be set on them: exposure time, image type, binning, window, cooling, gain.

Images never travel over the comm: ``grab_data`` writes the image through the virtual file system
and returns its path (and broadcasts a NewImageEvent with it).
"""

from __future__ import annotations

from abc import abstractmethod
from dataclasses import dataclass

from nightcrew.interfaces.base import Interface
from nightcrew.interfaces.control import IAbortable
from nightcrew.interfaces.enums import ExposureStatus, ImageType
from nightcrew.interfaces.quantities import ExposureTime, Gain, GainOffset, Temperature
from nightcrew.timeout import timeout

__all__ = [
    "Binning",
    "CoolingStatus",
    "IBinning",
    "ICamera",
    "ICooling",
    "IData",
    "IExposure",
    "IExposureTime",
    "IGain",
    "IImageType",
    "IStoppableExposure",
    "IVideo",
    "IWindow",
    "Window",
]


@dataclass(frozen=True)
class Binning:
    """Binning factors along the detector's x and y axes."""

    x: int
    y: int


@dataclass(frozen=True)
class Window:
    """A detector region in unbinned pixels; left/top are 0-based."""

    left: int
    top: int
    width: int
    height: int


@dataclass(frozen=True)
class CoolingStatus:
    """State of a detector's cooling."""

    enabled: bool
    setpoint: float  # °C
    power: float  # percent of the cooler's maximum
    temperature: float | None = None  # °C of the detector; None where the camera does not say


class IData(Interface):
    """A device that produces data files (images, spectra, video frames).

    ``grab_data(broadcast, image_type)``: with ``broadcast`` false no NewImageEvent is sent, so only
    the caller learns of the frame (an acquisition or focus frame no image pipeline should take);
    ``image_type`` None takes the one set with IImageType. Its announced timeout is at most 3600 s;
    nightcrew's cameras announce the exposure time set plus read-out, header round and margins
    (docs/protocol.md, section 4).
    """

    # No exposure-time argument to derive a timeout from: a generous fixed one, which
    # implementations replace with @timeout(lambda self, ...) computed from their settings.
    @timeout(3600)
    @abstractmethod
    async def grab_data(self, broadcast: bool = True, image_type: ImageType | None = None) -> str:
        """Take a frame and return its VFS path (sent in a NewImageEvent if ``broadcast``)."""


class IExposure(Interface):
    """A device whose exposures can be watched while they run."""

    @abstractmethod
    async def get_exposure_status(self) -> ExposureStatus:
        """What the device is doing now."""

    @abstractmethod
    async def get_exposure_progress(self) -> float:
        """Progress of the current exposure in percent (0-100); 0 when idle."""


class ICamera(IData, IAbortable, IExposure):
    """A camera: takes images, can be aborted and watched."""


class IStoppableExposure(Interface):
    """An exposure that can be ended early and still read out (ASCOM's StopExposure, not AbortExposure).

    The running ``grab_data`` then returns its frame as usual, with EXPTIME the seconds really
    exposed, EXPREQ the seconds asked for and ``CUTSHORT = T``; an abort, by contrast, keeps nothing.
    """

    @abstractmethod
    async def stop_exposure(self) -> None:
        """Close the shutter now, read out and keep the frame; nothing happens when not exposing."""


class IExposureTime(Interface):
    """A settable exposure time."""

    @abstractmethod
    async def set_exposure_time(self, exposure_time: ExposureTime) -> None:
        """Set the exposure time in seconds for the next frames (up to the camera's maximum)."""

    @abstractmethod
    async def get_exposure_time(self) -> float:
        """Exposure time in seconds."""

    @abstractmethod
    async def get_exposure_time_left(self) -> float:
        """Seconds left in the current exposure; 0 when not exposing."""


class IImageType(Interface):
    """A settable image type, written to the header of the next frames."""

    @abstractmethod
    async def set_image_type(self, image_type: ImageType) -> None:
        """Set the image type of the next frames."""

    @abstractmethod
    async def get_image_type(self) -> ImageType:
        """Image type of the next frames."""


class IBinning(Interface):
    """Pixel binning."""

    @abstractmethod
    async def set_binning(self, x: int, y: int) -> None:
        """Bin ``x`` by ``y`` pixels in the next frames."""

    @abstractmethod
    async def get_binning(self) -> Binning:
        """Current binning."""

    @abstractmethod
    async def list_binnings(self) -> list[Binning]:
        """Binnings the camera supports."""


class IWindow(Interface):
    """Reading out a sub-frame of the detector."""

    @abstractmethod
    async def get_full_frame(self) -> Window:
        """The whole detector."""

    @abstractmethod
    async def set_window(self, left: int, top: int, width: int, height: int) -> None:
        """Read out only this region (unbinned pixels, 0-based) in the next frames."""

    @abstractmethod
    async def get_window(self) -> Window:
        """Region read out in the next frames."""


class ICooling(Interface):
    """Detector cooling."""

    @abstractmethod
    async def set_cooling(self, enabled: bool, setpoint: Temperature) -> None:
        """Switch cooling on or off and set its target temperature in °C."""

    @abstractmethod
    async def get_cooling(self) -> CoolingStatus:
        """Cooling state, setpoint, power and the detector's temperature."""


class IGain(Interface):
    """Detector gain and offset (bias level), in the camera's own units."""

    @abstractmethod
    async def set_gain(self, gain: Gain) -> None:
        """Set the gain for the next frames."""

    @abstractmethod
    async def get_gain(self) -> float:
        """Current gain."""

    @abstractmethod
    async def set_offset(self, offset: GainOffset) -> None:
        """Set the offset (bias level) for the next frames."""

    @abstractmethod
    async def get_offset(self) -> float:
        """Current offset."""


class IVideo(IData):
    """A camera with a live video stream; grab_data saves the current frame."""

    @abstractmethod
    async def get_video(self) -> str:
        """URL of the video stream."""
