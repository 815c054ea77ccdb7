"""The base of all cameras: settings, checks, headers and files; drivers only expose.

A driver implements :meth:`BaseCamera._hw_full_frame` (the chip), optionally
:meth:`BaseCamera._hw_binnings`, and :meth:`BaseCamera._hw_expose`, which returns a
:class:`Frame` of uint16 pixels (shape: window size / binning) plus the driver's own cards
(e.g. CCD-TEMP). Settings are checked here with one clear InvalidArgumentError each and are
unchanged when refused; an exposure uses a snapshot of them, so changing a setting while exposing
affects only the next frame.

FITS keywords written by every camera: DATE-OBS, DATE-END (DATE-OBS + EXPTIME, the integration's
end), MJD-OBS, EXPTIME, IMAGETYP, XBINNING, YBINNING,
XORGSUBF, YORGSUBF (window origin in unbinned pixels), SITELAT,
SITELONG, SITEELEV (when the site is known), ORIGIN, plus the ``fits_headers`` of the configuration
(INSTRUME, TELESCOP, OBSERVER, ...) and whatever header providers add (telescope: RA, DEC,
OBJCTRA, OBJCTDEC, AIRMASS, PIERSIDE, ...; filter wheel: FILTER; focuser: FOCUS; mastermind: OBJECT
and the TASK-* cards).

Cooling cards, read when the exposure starts: CCD-TEMP (when the driver knows the detector's
temperature) and, while the cooler is on, SET-TEMP, COOLPOW (percent) and TEMP-OK (false when
CCD-TEMP is more than ``temperature_margin`` °C off SET-TEMP: such a frame goes into no master).
"""

from __future__ import annotations

import logging
import math
from abc import abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from nightcrew.errors import ConfigError, GrabImageError, InvalidArgumentError, NotSupportedError
from nightcrew.events import NewImageEvent
from nightcrew.images.calibration import TEMPERATURE_MARGIN, off_set_point
from nightcrew.interfaces import (
    Binning,
    CoolingStatus,
    FitsCard,
    IBinning,
    ICamera,
    ICooling,
    IExposureTime,
    IImageType,
    ImageType,
    IWindow,
    Window,
)
from nightcrew.modules.camera.exposing import ExposingModule, Frame
from nightcrew.timeout import timeout

__all__ = ["BaseCamera", "ExposureSettings"]

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ExposureSettings:
    """Everything the driver needs for one exposure (a snapshot taken when it starts)."""

    exposure_time: float
    image_type: ImageType
    binning: Binning
    window: Window

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, columns) of the image the driver must return."""
        return self.window.height // self.binning.y, self.window.width // self.binning.x

    @property
    def shutter_open(self) -> bool:
        return self.image_type not in (ImageType.BIAS, ImageType.DARK)


class BaseCamera(ExposingModule, ICamera, IExposureTime, IImageType, IBinning, IWindow, ICooling):
    """A camera; a driver implements the ``_hw_*`` hooks.

    Args:
        filename_pattern: VFS path of new images; placeholders are FITS keywords
            (default ``/cache/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits``).
        fits_headers: Fixed cards, e.g. ``{INSTRUME: ..., TELESCOP: ..., OBSERVER: ...}``.
        header_timeout: Clock seconds each header provider may take.
        expect_headers_from: Modules whose cards every frame should carry; a frame without them
            names them in ``HDRMISS`` (also the first after a restart of the camera).
        temperature_margin: °C the detector may be off its cooling set point in a good frame
            (TEMP-OK); a frame further off is written, flagged and logged.
        **kwargs: Module options.
    """

    default_pattern = "/cache/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits"

    def __init__(self, *, temperature_margin: float = TEMPERATURE_MARGIN, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not (math.isfinite(temperature_margin) and temperature_margin > 0):
            raise ConfigError(f"must be > 0 °C, got {temperature_margin}", key="temperature_margin")
        self._temperature_margin = float(temperature_margin)
        self._exposure_time = 1.0
        self._image_type = ImageType.OBJECT
        self._binning = Binning(1, 1)
        self._window = self._hw_full_frame()
        self._cooling = CoolingStatus(enabled=False, setpoint=-10.0, power=0.0)

    @classmethod
    def coldest_setpoint(cls, options: Mapping[str, Any]) -> float | None:
        """The lowest set point a camera built from ``options`` can reach, °C; None: unknown.

        ``nightcrew check`` refuses a cooling schedule that asks for less.
        """
        return None

    # --- hooks for drivers ---------------------------------------------------------------------

    @abstractmethod
    def _hw_full_frame(self) -> Window:
        """The whole chip in unbinned pixels (known from the constructor's arguments)."""

    def _hw_binnings(self) -> list[Binning]:
        """Binnings the camera supports."""
        return [Binning(1, 1)]

    @abstractmethod
    async def _hw_expose(self, settings: ExposureSettings) -> Frame:
        """Expose, read out and return the frame (uint16, shape ``settings.shape``).

        Cancelled when the exposure is aborted: stop the hardware in ``except CancelledError``.
        Call ``self._start_integration()`` when the shutter opens if anything comes first (DATE-OBS
        is then), and ``await self._set_exposure_status(ExposureStatus.READOUT)`` when reading out.
        """

    async def _hw_set_cooling(self, enabled: bool, setpoint: float) -> None:
        """Switch the cooler; the default camera has none."""
        raise NotSupportedError(f"{self.name} has no cooling")

    async def _hw_cooling_power(self) -> float:
        """Cooler power in percent."""
        return 0.0

    async def _hw_ccd_temperature(self) -> float | None:
        """The detector's temperature in °C; None: the camera does not say."""
        return None

    # --- ICamera -------------------------------------------------------------------------------

    # A hung exposure is noticed once it is overdue, not after IData's generic hour.
    @timeout(lambda self, image_type=None, **_: self.grab_timeout(image_type))
    async def grab_data(self, broadcast: bool = True, image_type: ImageType | None = None) -> str:
        self._check_not_busy()
        kind = self._image_type if image_type is None else ImageType(image_type)
        exposure_time = self._frame_exposure_time(kind)
        settings = ExposureSettings(exposure_time, kind, self._binning, self._window)
        cooling = await self.get_cooling()

        async def expose() -> Frame:
            return await self._hw_expose(settings)

        async def announce(filename: str) -> None:
            await self.comm.send_event(NewImageEvent(filename=filename, image_type=kind))

        return await self._take_exposure(
            expose,
            exposure_time,
            lambda frame: self._own_cards(settings, frame) | self._cooling_cards(cooling),
            announce if broadcast else None,
        )

    def grab_timeout(self, image_type: ImageType | None = None) -> float:
        """The timeout ``grab_data`` announces (see :meth:`ExposingModule._exposure_timeout`)."""
        kind = self._image_type if image_type is None else ImageType(image_type)
        return self._exposure_timeout(self._frame_exposure_time(kind))

    def _frame_exposure_time(self, kind: ImageType) -> float:
        # A bias is a zero-second dark by definition; no driver should have to know that.
        return 0.0 if kind is ImageType.BIAS else self._exposure_time

    def _own_cards(self, settings: ExposureSettings, frame: Frame) -> dict[str, FitsCard]:
        data = frame.data
        if data.ndim != 2 or data.shape != settings.shape:
            raise GrabImageError(f"driver returned an image of shape {data.shape}, expected {settings.shape}")
        if data.dtype.name != "uint16":
            raise GrabImageError(f"driver returned {data.dtype} pixels, expected uint16")
        cards: dict[str, FitsCard] = {
            "EXPTIME": (settings.exposure_time, "Exposure time [s]"),
            "IMAGETYP": (settings.image_type.value, "Image type"),
            "XBINNING": (settings.binning.x, "Binning along x"),
            "YBINNING": (settings.binning.y, "Binning along y"),
            "XORGSUBF": (settings.window.left, "Window origin x [unbinned px]"),
            "YORGSUBF": (settings.window.top, "Window origin y [unbinned px]"),
        }
        if self.site is not None:
            cards["SITELAT"] = (self.site.latitude, "Site latitude [deg]")
            cards["SITELONG"] = (self.site.longitude, "Site longitude, east positive [deg]")
            cards["SITEELEV"] = (self.site.elevation, "Site elevation [m]")
        return cards

    def _cooling_cards(self, cooling: CoolingStatus) -> dict[str, FitsCard]:
        cards: dict[str, FitsCard] = {}
        if cooling.temperature is not None:
            cards["CCD-TEMP"] = (round(cooling.temperature, 2), "Detector temperature [degC]")
        if cooling.enabled:
            cards["SET-TEMP"] = (cooling.setpoint, "Cooling setpoint [degC]")
            cards["COOLPOW"] = (round(cooling.power, 1), "Cooler power [%]")
        if cooling.enabled and cooling.temperature is not None:
            good = not off_set_point(
                {"CCD-TEMP": cooling.temperature, "SET-TEMP": cooling.setpoint}, self._temperature_margin
            )
            cards["TEMP-OK"] = (good, f"CCD-TEMP within {self._temperature_margin:g} degC of SET-TEMP")
            if not good:
                log.warning(
                    "%s: exposing at %.1f °C, off the set point %g °C by more than %g °C (TEMP-OK = F)",
                    self.name,
                    cooling.temperature,
                    cooling.setpoint,
                    self._temperature_margin,
                )
        return cards

    # --- settings ------------------------------------------------------------------------------

    async def set_exposure_time(self, exposure_time: float) -> None:
        self._exposure_time = self._checked_exposure_time(exposure_time)

    async def get_exposure_time(self) -> float:
        return self._exposure_time

    async def get_exposure_time_left(self) -> float:
        return self._exposure_time_left()

    async def set_image_type(self, image_type: ImageType) -> None:
        self._image_type = ImageType(image_type)

    async def get_image_type(self) -> ImageType:
        return self._image_type

    async def set_binning(self, x: int, y: int) -> None:
        supported = self._hw_binnings()
        if Binning(x, y) not in supported:
            names = ", ".join(f"{b.x}x{b.y}" for b in supported)
            raise InvalidArgumentError(f"binning {x}x{y} is not supported; supported: {names}")
        self._binning = Binning(x, y)

    async def get_binning(self) -> Binning:
        return self._binning

    async def list_binnings(self) -> list[Binning]:
        return list(self._hw_binnings())

    async def get_full_frame(self) -> Window:
        return self._hw_full_frame()

    async def set_window(self, left: int, top: int, width: int, height: int) -> None:
        full = self._hw_full_frame()
        inside = (
            left >= full.left
            and top >= full.top
            and width > 0
            and height > 0
            and left + width <= full.left + full.width
            and top + height <= full.top + full.height
        )
        if not inside:
            raise InvalidArgumentError(
                f"window (left={left}, top={top}, width={width}, height={height}) lies outside the chip "
                f"(left={full.left}, top={full.top}, width={full.width}, height={full.height})"
            )
        self._window = Window(left, top, width, height)

    async def get_window(self) -> Window:
        return self._window

    async def set_cooling(self, enabled: bool, setpoint: float) -> None:
        if not (math.isfinite(setpoint) and -100.0 <= setpoint <= 50.0):
            raise InvalidArgumentError(f"cooling setpoint must be within -100..50 °C, got {setpoint}")
        await self._hw_set_cooling(enabled, setpoint)
        self._cooling = CoolingStatus(enabled=enabled, setpoint=float(setpoint), power=self._cooling.power)

    async def _restore_cooling(self) -> None:
        """Switch the cooler on at the set point again if this module had (a device that restarted
        comes back with its cooler off); drivers call this after reading the device."""
        if self._cooling.enabled:
            log.info("%s: cooling to %g °C again", self.name, self._cooling.setpoint)
            await self._hw_set_cooling(True, self._cooling.setpoint)

    async def get_cooling(self) -> CoolingStatus:
        power = await self._hw_cooling_power() if self._cooling.enabled else 0.0
        return CoolingStatus(
            enabled=self._cooling.enabled,
            setpoint=self._cooling.setpoint,
            power=power,
            temperature=await self._hw_ccd_temperature(),
        )
