"""A nightcrew camera as an INDI CCD: exposures whose FITS files reach the client as BLOBs.

==========================  ======================================================================
property                    nightcrew
==========================  ======================================================================
CCD_EXPOSURE                set_exposure_time(), grab_data(); Busy with the seconds left, then the
                            written FITS file (read through the server's VFS) is sent as CCD1
CCD_ABORT_EXPOSURE          abort()
CCD1 (BLOB, ro)             the FITS file of the last exposure, format ``.fits``
CCD_FRAME                   set_window() in unbinned pixels (cameras with IWindow)
CCD_INFO (ro)               the full frame, pixel sizes (see below) and 16 bits per pixel (IWindow)
CCD_BINNING                 set_binning() (cameras with IBinning)
CCD_FRAME_TYPE              the image type given to grab_data(): LIGHT object, BIAS, DARK, FLAT skyflat
==========================  ======================================================================

Cooling, gain, CFA, compression, upload mode and pixel sizes: :mod:`.camera_indi_settings`.

The work on the module is the served camera role's (:mod:`nightcrew.modules.served.camera`), which
the Alpaca Camera shares. The camera writes the file through its own VFS, and the server reads it
through its own: give the server the camera's root (e.g. ``images``), or the exposure ends in Alert
naming the path.
"""

from __future__ import annotations

from typing import Any

from nightcrew.bridges.indi.server_vectors import (
    BlobMember,
    NumberMember,
    Permission,
    Property,
    PropertyState,
    SwitchMember,
    SwitchRule,
)
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import (
    Binning,
    ExposureStatus,
    IBinning,
    ICamera,
    IExposureTime,
    IImageType,
    ImageType,
    IWindow,
    Window,
)
from nightcrew.modules.served.camera import MAX_EXPOSURE, ServedCameraRole, read_frame
from nightcrew.modules.served.camera_indi_settings import CameraSettings, pixel_info_members
from nightcrew.modules.served.device_indi import MAIN_GROUP, ServedDevice, Values, switch_on

__all__ = ["ServedCamera"]

#: INDI frame types and the nightcrew image types they stand for.
FRAME_TYPES = {
    "FRAME_LIGHT": ImageType.OBJECT,
    "FRAME_BIAS": ImageType.BIAS,
    "FRAME_DARK": ImageType.DARK,
    "FRAME_FLAT": ImageType.SKYFLAT,
}
_SETTINGS = "Image Settings"


class ServedCamera(ServedDevice[ICamera]):
    """An ICamera module as an INDI CCD."""

    interface = ICamera
    driver_interface = 2

    @property
    def role(self) -> ServedCameraRole:
        return ServedCameraRole(self.device, self.name)

    async def _build(self) -> list[Property[Any]]:
        camera, name = self.device, self.name
        exposure_time = await camera.get_exposure_time() if isinstance(camera, IExposureTime) else 1.0
        self.exposure = Property(
            name,
            "CCD_EXPOSURE",
            "Expose",
            MAIN_GROUP,
            [
                NumberMember(
                    "CCD_EXPOSURE_VALUE", "Duration (s)", exposure_time, 0.0, MAX_EXPOSURE, 0.0, "%5.2f"
                )
            ],
            timeout=MAX_EXPOSURE,
        )
        self.abort = Property(
            name, "CCD_ABORT_EXPOSURE", "Abort", MAIN_GROUP, [SwitchMember("ABORT", "Abort")]
        )
        self.abort.rule = SwitchRule.AT_MOST_ONE
        self.image = Property(
            name, "CCD1", "Image Data", "Image Info", [BlobMember("CCD1", "Image")], perm=Permission.READ_ONLY
        )
        kind = await camera.get_image_type() if isinstance(camera, IImageType) else ImageType.OBJECT
        self.frame_type = Property(
            name,
            "CCD_FRAME_TYPE",
            "Frame Type",
            _SETTINGS,
            [SwitchMember(key, key[6:].title(), value is kind) for key, value in FRAME_TYPES.items()],
            state=PropertyState.OK,
        )
        if not any(m.on for m in self.frame_type.members):
            switch_on(self.frame_type, "FRAME_LIGHT")
        self.settings = CameraSettings(name, camera)
        vectors: list[Property[Any]] = [
            self.exposure,
            self.abort,
            self.image,
            self.frame_type,
            *self.settings.vectors,
        ]
        self.frame: Property[NumberMember] | None = None
        self.info: Property[NumberMember] | None = None
        self.binning: Property[NumberMember] | None = None
        if isinstance(camera, IWindow):
            full = await self.role.full_frame()
            self.frame = Property(
                name,
                "CCD_FRAME",
                "Frame",
                _SETTINGS,
                [
                    NumberMember("X", "Left", 0.0, full.left, full.left + full.width - 1, 1.0, "%4.0f"),
                    NumberMember("Y", "Top", 0.0, full.top, full.top + full.height - 1, 1.0, "%4.0f"),
                    NumberMember("WIDTH", "Width", 0.0, 1.0, full.width, 1.0, "%4.0f"),
                    NumberMember("HEIGHT", "Height", 0.0, 1.0, full.height, 1.0, "%4.0f"),
                ],
            )
            self.info = Property(
                name,
                "CCD_INFO",
                "CCD Information",
                "Image Info",
                pixel_info_members(full.width, full.height, self._link.pixel_size),
                perm=Permission.READ_ONLY,
                state=PropertyState.OK,
            )
            vectors += [self.frame, self.info]
        if isinstance(camera, IBinning):
            binnings = await self.role.binnings()
            self.binning = Property(
                name,
                "CCD_BINNING",
                "Binning",
                _SETTINGS,
                [
                    NumberMember("HOR_BIN", "X", 1.0, 1.0, max(b.x for b in binnings), 1.0, "%2.0f"),
                    NumberMember("VER_BIN", "Y", 1.0, 1.0, max(b.y for b in binnings), 1.0, "%2.0f"),
                ],
            )
            vectors.append(self.binning)
        return vectors

    async def _update(self) -> None:
        camera = self.device
        status = await camera.get_exposure_status()
        exposing = status in (ExposureStatus.EXPOSING, ExposureStatus.READOUT)
        if exposing and isinstance(camera, IExposureTime):
            self.exposure.by_name["CCD_EXPOSURE_VALUE"].value = round(
                await camera.get_exposure_time_left(), 3
            )
        self._follow(self.exposure, busy=exposing, failed=status is ExposureStatus.ERROR)
        temperature = self.settings.temperature
        await self.settings.update(camera, temperature is not None and self.acting(temperature))
        if self.frame is not None and isinstance(camera, IWindow):
            window = await camera.get_window()
            for key, value in (
                ("X", window.left),
                ("Y", window.top),
                ("WIDTH", window.width),
                ("HEIGHT", window.height),
            ):
                self.frame.by_name[key].value = float(value)
            self._follow(self.frame, busy=False)
        if self.binning is not None and isinstance(camera, IBinning):
            binning = await camera.get_binning()
            self.binning.by_name["HOR_BIN"].value = float(binning.x)
            self.binning.by_name["VER_BIN"].value = float(binning.y)
            self._follow(self.binning, busy=False)

    async def _request(self, vector: Property[Any], values: Values) -> None:
        camera = self.device
        if vector is self.exposure:
            self._start(self.exposure, self._expose(float(values["CCD_EXPOSURE_VALUE"])))
        elif vector is self.abort:
            self.abort.by_name["ABORT"].on = False
            if values.get("ABORT"):
                self._start(self.abort, camera.abort())
        elif vector is self.frame_type:
            switch_on(self.frame_type, next(name for name, on in values.items() if on))
            self.frame_type.state = PropertyState.OK
            self._link.publish(self.frame_type)
        elif vector is self.frame and isinstance(camera, IWindow):
            merged = {m.name: round(float(values.get(m.name, m.value))) for m in vector.members}
            window = Window(merged["X"], merged["Y"], merged["WIDTH"], merged["HEIGHT"])
            self._start(vector, self.role.set_window(window))
        elif vector is self.binning and isinstance(camera, IBinning):
            x = round(float(values.get("HOR_BIN", vector.by_name["HOR_BIN"].value)))
            y = round(float(values.get("VER_BIN", vector.by_name["VER_BIN"].value)))
            self._start(vector, self.role.set_binning(Binning(x, y)))
        elif self.settings.owns(vector):
            action = await self.settings.request(camera, vector, values)
            for key, value in values.items():  # the client's choice shows until the device says
                member = vector.by_name[key]
                if isinstance(member, SwitchMember):
                    member.on = bool(value)
            if action is None:
                vector.state = PropertyState.OK
                self._link.publish(vector)
            else:
                self._start(vector, action)
        else:
            raise InvalidArgumentError(f"{vector.where} cannot be set")

    async def _expose(self, seconds: float) -> None:
        role = self.role
        await role.set_exposure_time(seconds)
        kind = next(FRAME_TYPES[m.name] for m in self.frame_type.members if m.on)
        data = await read_frame(self._link.vfs, await role.grab(kind))
        for vector in self.settings.read_frame(data, self.info):
            self._link.publish(vector)
        self.exposure.by_name["CCD_EXPOSURE_VALUE"].value = 0.0
        self.image.state = PropertyState.OK
        self._link.publish_blob(self.image, "CCD1", data, ".fits")
