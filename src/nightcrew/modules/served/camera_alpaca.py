"""The served camera's Alpaca adapter: a nightcrew camera (ICamera) as an Alpaca Camera.

Alpaca sets binning and the sub-frame (StartX/StartY/NumX/NumY, in binned pixels) as properties of
the driver and applies them when an exposure starts; nightcrew keeps them on the camera module.
So this device keeps the Alpaca values and hands them to the module in StartExposure (binning,
window in unbinned pixels, exposure time, image type: light frames OBJECT, dark frames DARK,
zero-second dark frames BIAS), then runs ``grab_data()`` in the background. Until a client sets
the sub-frame, every exposure reads the full chip at the current binning. StopExposure ends the
exposure early and keeps it when the module can (IStoppableExposure; CanStopExposure says so), and
LastExposureDuration is then the time the frame's header says it exposed.

The work on the module is the served camera role's (:mod:`nightcrew.modules.served.camera`), which
the INDI CCD shares. ImageArray serves the pixels of the frame the role read back through the
server's VFS, as ImageBytes when the client accepts ``application/imagebytes``, else as JSON.
"""

from __future__ import annotations

import asyncio
import io
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from nightcrew.bridges.alpaca.errors import AlpacaInvalidOperationError
from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest, ImageArray
from nightcrew.errors import DeviceBusyError, GrabImageError, InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import Binning, ExposureStatus, ICamera, ICooling, ImageType, Window
from nightcrew.modules.served.camera import MAX_EXPOSURE, ServedCameraRole, read_frame

__all__ = ["ServedCamera"]

#: CameraStates.
_IDLE, _WAITING, _EXPOSING, _READING, _ERROR = 0, 1, 2, 3, 5
_STATES = {ExposureStatus.EXPOSING: _EXPOSING, ExposureStatus.READOUT: _READING, ExposureStatus.ERROR: _ERROR}


@dataclass
class _Exposure:
    """The last exposure: what was asked, and the file and pixels it gave."""

    duration: float
    start_time: str
    path: str | None = None
    pixels: npt.NDArray[Any] | None = None
    stopped: bool = False  # the duration comes from the file


class ServedCamera(ServedDevice):
    """Alpaca Camera (ICameraV4 members) on a nightcrew ICamera module.

    Args:
        pixel_size: Pixel size in µm (the interface does not tell it).
    """

    device_type = "camera"
    type_name = "Camera"
    interface_version = 4  # ICameraV4 (Platform 7): V3 plus Connect/Disconnect and DeviceState
    state_members = ("CameraState", "ImageReady", "IsPulseGuiding", "PercentCompleted")
    interface = ICamera

    def __init__(self, *args: Any, pixel_size: float | None = None, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._pixel_size = pixel_size
        self._bin = Binning(1, 1)
        self._subframe: tuple[int, int, int, int] | None = None  # start x, y, num x, y (binned)
        self._last: _Exposure | None = None

    async def _role(self) -> ServedCameraRole:
        return ServedCameraRole(await self.proxy(ICamera), self.module)

    async def _full_frame(self) -> Window:
        return await (await self._role()).full_frame()

    async def _binnings(self) -> list[Binning]:
        return await (await self._role()).binnings()

    # --- the chip ------------------------------------------------------------------------------

    async def get_cameraxsize(self, request: AlpacaRequest) -> int:
        return (await self._full_frame()).width

    async def get_cameraysize(self, request: AlpacaRequest) -> int:
        return (await self._full_frame()).height

    async def get_maxbinx(self, request: AlpacaRequest) -> int:
        return max(b.x for b in await self._binnings())

    async def get_maxbiny(self, request: AlpacaRequest) -> int:
        return max(b.y for b in await self._binnings())

    async def get_canasymmetricbin(self, request: AlpacaRequest) -> bool:
        return any(b.x != b.y for b in await self._binnings())

    async def get_pixelsizex(self, request: AlpacaRequest) -> float:
        if self._pixel_size is None:
            raise NotSupportedError(f"pixelsize: no pixel size configured for {self.module} (pixel_sizes)")
        return self._pixel_size

    get_pixelsizey = get_pixelsizex

    async def get_maxadu(self, request: AlpacaRequest) -> int:
        return 65535

    async def get_exposuremin(self, request: AlpacaRequest) -> float:
        return 0.0

    async def get_exposuremax(self, request: AlpacaRequest) -> float:
        return MAX_EXPOSURE

    async def get_exposureresolution(self, request: AlpacaRequest) -> float:
        return 0.001

    async def get_sensortype(self, request: AlpacaRequest) -> int:
        return 0  # monochrome

    async def get_hasshutter(self, request: AlpacaRequest) -> bool:
        return True

    async def get_canabortexposure(self, request: AlpacaRequest) -> bool:
        return True

    async def get_canstopexposure(self, request: AlpacaRequest) -> bool:
        return (await self._role()).stoppable is not None

    async def get_canpulseguide(self, request: AlpacaRequest) -> bool:
        return False

    get_cangetcoolerpower = get_cansetccdtemperature = get_canfastreadout = get_canpulseguide

    async def get_readoutmode(self, request: AlpacaRequest) -> int:
        return 0

    async def put_readoutmode(self, request: AlpacaRequest) -> None:
        mode = request.integer("ReadoutMode")
        if mode != 0:
            raise InvalidArgumentError(f"readoutmode must be 0 (the only mode), got {mode}")

    async def get_readoutmodes(self, request: AlpacaRequest) -> list[str]:
        return ["Default"]

    async def get_cooleron(self, request: AlpacaRequest) -> bool:
        cooling = await self.optional(ICooling)
        return False if cooling is None else (await cooling.get_cooling()).enabled

    # --- binning and sub-frame -----------------------------------------------------------------

    async def get_binx(self, request: AlpacaRequest) -> int:
        return self._bin.x

    async def get_biny(self, request: AlpacaRequest) -> int:
        return self._bin.y

    async def put_binx(self, request: AlpacaRequest) -> None:
        await self._set_bin(request.integer("BinX"), None)

    async def put_biny(self, request: AlpacaRequest) -> None:
        await self._set_bin(None, request.integer("BinY"))

    async def _set_bin(self, x: int | None, y: int | None) -> None:
        binnings = await self._binnings()
        value = x if x is not None else y
        allowed = sorted({b.x if x is not None else b.y for b in binnings})
        if value not in allowed:
            axis = "binx" if x is not None else "biny"
            raise InvalidArgumentError(f"{axis} must be one of {allowed}, got {value}")
        if not any(b.x != b.y for b in binnings):
            self._bin = Binning(int(value), int(value))  # symmetric cameras bin both axes alike
        else:
            self._bin = Binning(x if x is not None else self._bin.x, y if y is not None else self._bin.y)

    async def _subframe_values(self) -> tuple[int, int, int, int]:
        if self._subframe is not None:
            return self._subframe
        full = await self._full_frame()
        return 0, 0, full.width // self._bin.x, full.height // self._bin.y

    async def get_startx(self, request: AlpacaRequest) -> int:
        return (await self._subframe_values())[0]

    async def get_starty(self, request: AlpacaRequest) -> int:
        return (await self._subframe_values())[1]

    async def get_numx(self, request: AlpacaRequest) -> int:
        return (await self._subframe_values())[2]

    async def get_numy(self, request: AlpacaRequest) -> int:
        return (await self._subframe_values())[3]

    async def _set_subframe(self, index: int, name: str, request: AlpacaRequest) -> None:
        value = request.integer(name)
        if value < (1 if index >= 2 else 0):
            raise InvalidArgumentError(
                f"{name.lower()} must be {'> 0' if index >= 2 else '>= 0'}, got {value}"
            )
        values = list(await self._subframe_values())
        values[index] = value
        self._subframe = (values[0], values[1], values[2], values[3])

    async def put_startx(self, request: AlpacaRequest) -> None:
        await self._set_subframe(0, "StartX", request)

    async def put_starty(self, request: AlpacaRequest) -> None:
        await self._set_subframe(1, "StartY", request)

    async def put_numx(self, request: AlpacaRequest) -> None:
        await self._set_subframe(2, "NumX", request)

    async def put_numy(self, request: AlpacaRequest) -> None:
        await self._set_subframe(3, "NumY", request)

    # --- exposing ------------------------------------------------------------------------------

    async def put_startexposure(self, request: AlpacaRequest) -> None:
        duration, light = request.number("Duration"), request.boolean("Light")
        if not 0.0 <= duration <= MAX_EXPOSURE:
            raise InvalidArgumentError(f"duration must be within 0..{MAX_EXPOSURE:g} s, got {duration}")
        if self.action.running:
            raise DeviceBusyError(f"{self.describe()} is already exposing; wait for ImageReady or abort")
        role = await self._role()
        await self._apply_settings(role, duration)
        kind = ImageType.OBJECT if light else ImageType.DARK if duration > 0 else ImageType.BIAS
        exposure = _Exposure(duration, self.owner.clock.now().strftime("%Y-%m-%dT%H:%M:%S.%f"))
        self._last = exposure

        async def grab() -> None:
            exposure.path = await role.grab(kind)

        self.action.start("startexposure", grab)
        await self.action.settle(self.settle_time)

    async def _apply_settings(self, role: ServedCameraRole, duration: float) -> None:
        """Hand binning, window (Alpaca's is in binned pixels) and exposure time to the module."""
        await role.set_binning(self._bin)
        if role.window is not None:
            start_x, start_y, num_x, num_y = await self._subframe_values()
            bx, by = self._bin.x, self._bin.y
            await role.set_window(Window(start_x * bx, start_y * by, num_x * bx, num_y * by))
        await role.set_exposure_time(duration)

    async def put_abortexposure(self, request: AlpacaRequest) -> None:
        camera = await self.proxy(ICamera)
        if self.action.running:
            await camera.abort()
        await self.action.cancel()

    async def put_stopexposure(self, request: AlpacaRequest) -> None:
        stoppable = (await self._role()).stoppable
        if stoppable is None:
            raise NotSupportedError(f"module {self.module} cannot stop an exposure early; abort it")
        if self.action.running and self._last is not None:
            self._last.stopped = True
            await stoppable.stop_exposure()

    async def get_camerastate(self, request: AlpacaRequest) -> int:
        if not self.action.running:
            return _IDLE
        status = await (await self.proxy(ICamera)).get_exposure_status()
        return _STATES.get(status, _WAITING)  # idle while the module prepares the exposure

    async def get_imageready(self, request: AlpacaRequest) -> bool:
        self.action.raise_failure()
        return not self.action.running and self._last is not None and self._last.path is not None

    async def get_percentcompleted(self, request: AlpacaRequest) -> int:
        if self.action.running:
            return round(await (await self.proxy(ICamera)).get_exposure_progress())
        return 100 if await self.get_imageready(request) else 0

    def _taken(self, member: str) -> _Exposure:
        if self._last is None:
            raise AlpacaInvalidOperationError(f"{member}: no exposure has been started yet")
        return self._last

    async def get_lastexposureduration(self, request: AlpacaRequest) -> float:
        exposure = self._taken("lastexposureduration")
        if exposure.stopped and await self.get_imageready(request):
            await self._load(exposure)
        return exposure.duration

    async def get_lastexposurestarttime(self, request: AlpacaRequest) -> str:
        return self._taken("lastexposurestarttime").start_time

    async def get_imagearray(self, request: AlpacaRequest) -> ImageArray:
        if not await self.get_imageready(request):
            raise DeviceBusyError(f"{self.describe()}: no image is ready (ImageReady is false)")
        exposure = self._taken("imagearray")
        return ImageArray(await self._load(exposure))

    async def _load(self, exposure: _Exposure) -> npt.NDArray[Any]:
        """The exposure's pixels, read once from its file (a stopped one: its real duration too)."""
        if exposure.pixels is None:
            assert exposure.path is not None
            payload = await read_frame(self.owner.vfs, exposure.path)
            pixels, exposed = await asyncio.to_thread(_blocking_pixels, payload, exposure.path)
            exposure.pixels, exposure.duration = pixels, exposed if exposure.stopped else exposure.duration
        return exposure.pixels


def _blocking_pixels(payload: bytes, path: str) -> tuple[npt.NDArray[Any], float]:
    """The primary image of a FITS file, as the camera wrote it (uint16 stays uint16), and its EXPTIME."""
    from astropy.io import fits  # type: ignore[import-untyped]

    try:
        with fits.open(io.BytesIO(payload), do_not_scale_image_data=False) as hdul:
            data = hdul[0].data
            if data is None or data.ndim != 2:
                raise GrabImageError(f"{path} holds no two-dimensional image")
            # BZERO-scaled uint16 comes back as uint16; anything else keeps its own type.
            return np.array(data), float(hdul[0].header.get("EXPTIME", 0.0))
    except OSError as exc:
        raise GrabImageError(f"cannot read the frame {path}: {exc}") from exc
