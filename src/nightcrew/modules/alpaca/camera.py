"""AlpacaCamera: an ASCOM Alpaca camera on the camera base (settings, FITS, headers, events).

The base does everything a camera shares (checks, header providers, one atomic FITS write, events);
this driver only exposes: it sets binning and subframe (``BinX/BinY``, ``StartX/StartY/NumX/NumY``
in binned pixels), calls ``StartExposure``, polls ``ImageReady`` and ``CameraState`` and downloads
``ImageArray`` as ImageBytes (JSON if the device offers nothing else). A download of the wrong size,
a camera in error state or a device that goes away mid-exposure fails the exposure with one
GrabImageError naming the device and the call; the base writes no file then. ``stop_exposure``
(IStoppableExposure) calls ``StopExposure``: the device reads out early and the frame is kept with
EXPTIME the seconds from the start to the stop; a device whose ``CanStopExposure`` is false refuses
it with NotSupportedError (the scripts then abort).

The chip size and binnings come from the device when it connects; until then the camera knows
no chip (a 1x1 placeholder). Gain and offset follow IGain; the readout mode is the run-time config
option ``readout_mode`` (choices: the device's ReadoutModes).

On every (re)connect, before the module reports ready, an exposure the device is still running
(CameraState waiting, exposing or reading - e.g. started by a camera module that was killed) is
aborted (``AbortExposure``, else ``StopExposure``), so the next ``grab_data`` does not find the
camera busy. After a server restart the cooler and its set point are set again as they were.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any, cast

import numpy as np
import numpy.typing as npt

from nightcrew.errors import (
    AbortedError,
    ConfigError,
    GrabImageError,
    InvalidArgumentError,
    NightcrewError,
    NotSupportedError,
)
from nightcrew.interfaces import Binning, ExposureStatus, IGain, IStoppableExposure, Window
from nightcrew.modules.alpaca.device import LOST_DEVICE_ERRORS, AlpacaModule
from nightcrew.modules.camera import BaseCamera, ExposureSettings, Frame

__all__ = ["AlpacaCamera"]

log = logging.getLogger(__name__)

#: Alpaca CameraStates.
_IDLE, _WAITING, _READING, _ERROR = 0, 1, 3, 5


class AlpacaCamera(AlpacaModule, BaseCamera, IGain, IStoppableExposure):
    """A camera reached over ASCOM Alpaca.

    Args:
        readout_timeout: Wall seconds readout and download may take after the exposure time.
        **kwargs: ``server``, ``device_number`` and the other Alpaca options (AlpacaModule), and the
            camera's (``filename_pattern``, ``fits_headers``, ...).
    """

    device_type = "camera"

    def __init__(self, *, readout_timeout: float = 120.0, **kwargs: Any) -> None:
        self._chip = Window(0, 0, 1, 1)
        self._binnings = [Binning(1, 1)]
        self._gains: list[str] = []
        self._readout_modes: list[str] = []
        self._can_stop = False
        super().__init__(**kwargs)
        if not readout_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {readout_timeout}", key="readout_timeout")
        self._readout_timeout = float(readout_timeout)

    async def _on_connected(self) -> None:
        chip = Window(0, 0, int(await self._get("cameraxsize")), int(await self._get("cameraysize")))
        max_x, max_y = int(await self._get("maxbinx")), int(await self._get("maxbiny"))
        asymmetric = bool(await self._get("canasymmetricbin"))
        self._binnings = [
            Binning(x, y)
            for x in range(1, max_x + 1)
            for y in range(1, max_y + 1)
            if (asymmetric or x == y) and chip.width // x > 0 and chip.height // y > 0
        ]
        self._gains = await self._optional_list("gains")
        self._readout_modes = await self._optional_list("readoutmodes")
        self._can_stop = await self._optional_flag("canstopexposure")
        await self._read_exposure_range()
        if chip != self._chip:
            self._chip, self._window, self._binning = chip, chip, Binning(1, 1)
        if not self._busy:  # a reconnect during our own exposure: that exposure fails by itself
            await self._abort_leftover_exposure()
        await self._restore_cooling()

    async def _abort_leftover_exposure(self) -> None:
        """Abort an exposure the device still runs that no exposure of ours waits for."""
        state = await self._get("camerastate")
        if not _WAITING <= state <= _READING:
            return
        if await self._optional_flag("canabortexposure"):
            how = "abortexposure"
        elif self._can_stop:
            how = "stopexposure"
        else:  # it ends by itself; until then an exposure fails as a device fault and is retried
            log.warning(
                "%s: %s is still exposing and can neither abort nor stop", self.name, self.device.name
            )
            return
        log.warning("%s: %s is still exposing (CameraState %s): %s", self.name, self.device.name, state, how)
        await self._put(how)
        await self._poll_until(
            "camerastate",
            lambda s: s == _IDLE,
            self._readout_timeout,
            "aborting the exposure",
            GrabImageError,
        )

    async def _read_exposure_range(self) -> None:
        """Narrow the accepted exposure times to the device's ExposureMin..ExposureMax."""
        try:
            low, high = float(await self._get("exposuremin")), float(await self._get("exposuremax"))
        except (NightcrewError, TypeError, ValueError):  # optional in practice: keep the configured range
            return
        self._set_device_exposure_range(low, high)

    async def _optional_flag(self, member: str) -> bool:
        try:
            return bool(await self._get(member))
        except NightcrewError:
            return False

    async def _optional_list(self, member: str) -> list[str]:
        try:
            return [str(v) for v in await self._get(member)]
        except NightcrewError:  # not every camera has named gains or readout modes
            return []

    # --- hooks ---------------------------------------------------------------------------------

    def _hw_readout_allowance(self) -> float:
        return 2 * self._readout_timeout  # waiting for ImageReady, then downloading ImageArray

    def _hw_full_frame(self) -> Window:
        return self._chip

    def _hw_binnings(self) -> list[Binning]:
        return list(self._binnings)

    async def _hw_expose(self, settings: ExposureSettings) -> Frame:
        try:
            return await self._expose(settings)
        except (asyncio.CancelledError, AbortedError, GrabImageError):
            raise
        except NightcrewError as exc:
            raise GrabImageError(f"exposure failed: {exc}") from exc

    async def _expose(self, settings: ExposureSettings) -> Frame:
        binning, window = settings.binning, settings.window
        await self._put("binx", BinX=binning.x)
        await self._put("biny", BinY=binning.y)
        await self._put("startx", StartX=window.left // binning.x)
        await self._put("starty", StartY=window.top // binning.y)
        await self._put("numx", NumX=window.width // binning.x)
        await self._put("numy", NumY=window.height // binning.y)
        await self._put("startexposure", Duration=settings.exposure_time, Light=settings.shutter_open)
        self._start_integration()
        stopper = asyncio.ensure_future(self._stop_when_asked())
        try:
            await self._wait_for_image(settings.exposure_time)
        except asyncio.CancelledError:
            await asyncio.shield(self._put_best_effort("abortexposure"))
            raise
        finally:
            stopper.cancel()
        try:
            data = await self.device.image_array(time_limit=self._readout_timeout)
        except LOST_DEVICE_ERRORS as exc:
            self._connection_lost(str(exc))
            raise
        # CCD-TEMP: the camera base reads it (``_hw_ccd_temperature``) when the exposure starts.
        return Frame(_as_uint16(data, settings.shape, self.device.name), {})

    async def stop_exposure(self) -> None:
        if not self._can_stop:
            raise NotSupportedError(f"{self.device.name} cannot stop an exposure (CanStopExposure is false)")
        await super().stop_exposure()

    async def _stop_when_asked(self) -> None:
        await self._stop_requested.wait()
        try:
            await self._put("stopexposure")
        except NightcrewError as exc:  # the exposure runs to its end and is kept whole
            log.warning("%s: stopping the exposure failed: %s", self.name, exc)
            return
        self._cut_short(self.clock.time() - self._exposure_start)  # the shutter closed now

    async def _wait_for_image(self, exposure_time: float) -> None:
        async def image_ready() -> None:
            while True:
                state = await self._get("camerastate")
                if state == _ERROR:
                    raise GrabImageError(f"{self.device.name}: the camera reports an error (CameraState 5)")
                if state == _READING:
                    await self._set_exposure_status(ExposureStatus.READOUT)
                if await self._get("imageready"):
                    return
                await asyncio.sleep(self._poll_interval)

        limit = exposure_time + self._readout_timeout
        try:
            async with asyncio.timeout(limit):
                await image_ready()
        except TimeoutError:
            raise GrabImageError(f"{self.device.name}: no image within {limit:g} s") from None
        await self._set_exposure_status(ExposureStatus.READOUT)

    async def _hw_set_cooling(self, enabled: bool, setpoint: float) -> None:
        if enabled:
            await self._put("setccdtemperature", SetCCDTemperature=setpoint)
        await self._put("cooleron", CoolerOn=enabled)

    async def _hw_cooling_power(self) -> float:
        try:
            return float(await self._get("coolerpower"))
        except NightcrewError:
            return 0.0

    async def _hw_ccd_temperature(self) -> float | None:
        try:
            return float(await self._get("ccdtemperature"))
        except NightcrewError:  # not implemented by the camera: it does not say
            return None

    # --- IGain ---------------------------------------------------------------------------------

    async def set_gain(self, gain: float) -> None:
        if self._gains and not (0 <= gain < len(self._gains) and float(gain).is_integer()):
            raise InvalidArgumentError(f"gain must be an index into {self._gains}, got {gain}")
        await self._put("gain", Gain=int(gain))

    async def get_gain(self) -> float:
        return float(await self._get("gain"))

    async def set_offset(self, offset: float) -> None:
        await self._put("offset", Offset=int(offset))

    async def get_offset(self) -> float:
        return float(await self._get("offset"))

    # --- config options ------------------------------------------------------------------------

    async def _get_config_readout_mode(self) -> str:
        index = int(await self._get("readoutmode"))
        return self._readout_modes[index] if 0 <= index < len(self._readout_modes) else str(index)

    async def _set_config_readout_mode(self, value: str) -> None:
        if value not in self._readout_modes:
            raise InvalidArgumentError(
                f"unknown readout mode {value!r}; known: {', '.join(self._readout_modes)}"
            )
        await self._put("readoutmode", ReadoutMode=self._readout_modes.index(value))

    def _get_config_options_readout_mode(self) -> list[str]:
        return list(self._readout_modes)


def _as_uint16(data: npt.NDArray[Any], shape: tuple[int, int], device: str) -> npt.NDArray[np.uint16]:
    """The downloaded pixels as uint16 of the expected shape; GrabImageError naming what differs."""
    if data.shape != shape:
        raise GrabImageError(f"{device}: GET imagearray: got an image of {data.shape}, expected {shape}")
    if data.dtype == np.uint16:
        return cast(npt.NDArray[np.uint16], data)  # a view of the download: the FITS writer copies once
    pixels: npt.NDArray[np.uint16] = np.clip(data, 0, 65535).astype(np.uint16)
    return pixels
