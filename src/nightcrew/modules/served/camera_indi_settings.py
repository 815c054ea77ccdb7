"""A served camera's cooling, gain, colour pattern, compression, upload mode and pixel size.

==========================  ======================================================================
property                    nightcrew
==========================  ======================================================================
CCD_TEMPERATURE             get_cooling() temperature (ICooling); a client's value: set_cooling()
                            on at that set point; Busy until the detector is within 1 °C of it
CCD_COOLER                  COOLER_ON/OFF: set_cooling() at the current set point
CCD_COOLER_POWER (ro)       get_cooling() power, percent
CCD_GAIN                    GAIN: get_gain()/set_gain() (IGain; Ekos reads CCD_GAIN before the
                            generic CCD_CONTROLS, as the INDI CCD simulator serves it)
CCD_CFA (ro)                the FITS BAYERPAT of the last frame; CFA_TYPE empty: a mono camera
CCD_COMPRESSION             CCD_RAW only (frames go as written); CCD_COMPRESS ends in Alert
UPLOAD_MODE                 UPLOAD_CLIENT only: frames go to the client as BLOBs and stay in
                            nightcrew's archive; LOCAL or BOTH end in Alert
CCD_INFO pixel sizes        the server's ``pixel_size`` (µm) until a frame says otherwise: then
                            its XPIXSZ/YPIXSZ divided by XBINNING/YBINNING
==========================  ======================================================================
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.bridges.indi.server_vectors import (
    NumberMember,
    Permission,
    Property,
    PropertyState,
    SwitchMember,
    TextMember,
)
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import ICamera, ICooling, IGain
from nightcrew.modules.served.device_indi import MAIN_GROUP, switch_on

if TYPE_CHECKING:
    from nightcrew.modules.served.device_indi import Values

__all__ = ["CameraSettings", "pixel_info_members"]

#: Degrees °C from the set point within which the detector counts as there.
AT_SETPOINT = 1.0
_SETTINGS = "Image Settings"


def pixel_info_members(width: float, height: float, pixel_size: float) -> list[NumberMember]:
    """CCD_INFO's members in INDI's order."""
    return [
        NumberMember("CCD_MAX_X", "Max. Width", width, 1.0, 1e6, 1.0, "%4.0f"),
        NumberMember("CCD_MAX_Y", "Max. Height", height, 1.0, 1e6, 1.0, "%4.0f"),
        NumberMember("CCD_PIXEL_SIZE", "Pixel size (um)", pixel_size, 0.0, 100.0, 0.0, "%5.2f"),
        NumberMember("CCD_PIXEL_SIZE_X", "Pixel size X", pixel_size, 0.0, 100.0, 0.0, "%5.2f"),
        NumberMember("CCD_PIXEL_SIZE_Y", "Pixel size Y", pixel_size, 0.0, 100.0, 0.0, "%5.2f"),
        NumberMember("CCD_BITSPERPIXEL", "Bits per pixel", 16.0, 8.0, 64.0, 1.0, "%3.0f"),
    ]


class CameraSettings:
    """The settings properties of one served camera (those its interfaces allow)."""

    def __init__(self, device: str, camera: ICamera) -> None:
        self.temperature: Property[NumberMember] | None = None
        self.cooler: Property[SwitchMember] | None = None
        self.cooler_power: Property[NumberMember] | None = None
        self.gain: Property[NumberMember] | None = None
        if isinstance(camera, ICooling):
            self.temperature = Property(
                device,
                "CCD_TEMPERATURE",
                "Temperature",
                MAIN_GROUP,
                [NumberMember("CCD_TEMPERATURE_VALUE", "Temperature (C)", 0.0, -60.0, 40.0, 0.5, "%5.2f")],
                timeout=600.0,
            )
            self.cooler = Property(
                device,
                "CCD_COOLER",
                "Cooler",
                MAIN_GROUP,
                [SwitchMember("COOLER_ON", "On"), SwitchMember("COOLER_OFF", "Off", True)],
            )
            self.cooler_power = Property(
                device,
                "CCD_COOLER_POWER",
                "Cooling Power",
                MAIN_GROUP,
                [NumberMember("CCD_COOLER_VALUE", "Power (%)", 0.0, 0.0, 100.0, 1.0, "%3.0f")],
                perm=Permission.READ_ONLY,
            )
        if isinstance(camera, IGain):
            self.gain = Property(
                device,
                "CCD_GAIN",
                "Gain",
                MAIN_GROUP,
                [NumberMember("GAIN", "Gain", 0.0, 0.0, 1_000_000.0, 1.0, "%g")],
            )
        self.cfa = Property(
            device,
            "CCD_CFA",
            "Bayer Info",
            "Image Info",
            [
                TextMember("CFA_OFFSET_X", "X Offset", "0"),
                TextMember("CFA_OFFSET_Y", "Y Offset", "0"),
                TextMember("CFA_TYPE", "Filter", ""),
            ],
            perm=Permission.READ_ONLY,
            state=PropertyState.OK,
        )
        self.compression = Property(
            device,
            "CCD_COMPRESSION",
            "Image",
            _SETTINGS,
            [SwitchMember("CCD_COMPRESS", "Compress"), SwitchMember("CCD_RAW", "Raw", True)],
            state=PropertyState.OK,
        )
        self.upload_mode = Property(
            device,
            "UPLOAD_MODE",
            "Upload",
            "Options",
            [
                SwitchMember("UPLOAD_CLIENT", "Client", True),
                SwitchMember("UPLOAD_LOCAL", "Local"),
                SwitchMember("UPLOAD_BOTH", "Both"),
            ],
            state=PropertyState.OK,
        )

    @property
    def vectors(self) -> list[Property[Any]]:
        optional = [self.temperature, self.cooler, self.cooler_power, self.gain]
        return [v for v in optional if v is not None] + [self.cfa, self.compression, self.upload_mode]

    def owns(self, vector: Property[Any]) -> bool:
        return any(vector is v for v in self.vectors)

    async def update(self, camera: ICamera, acting: bool) -> None:
        """Read cooling and gain; ``acting``: a client's temperature request runs (its state stays)."""
        if self.temperature is not None and self.cooler is not None and isinstance(camera, ICooling):
            status = await camera.get_cooling()
            temperature = status.setpoint if status.temperature is None else status.temperature
            self.temperature.by_name["CCD_TEMPERATURE_VALUE"].value = round(temperature, 2)
            if not acting:
                cooling_down = status.enabled and abs(temperature - status.setpoint) > AT_SETPOINT
                self.temperature.state = PropertyState.BUSY if cooling_down else PropertyState.OK
            switch_on(self.cooler, "COOLER_ON" if status.enabled else "COOLER_OFF")
            self.cooler.state = PropertyState.BUSY if status.enabled else PropertyState.IDLE
            if self.cooler_power is not None:
                self.cooler_power.by_name["CCD_COOLER_VALUE"].value = round(status.power, 1)
                self.cooler_power.state = PropertyState.OK
        if self.gain is not None and isinstance(camera, IGain):
            self.gain.by_name["GAIN"].value = await camera.get_gain()
            if self.gain.state is PropertyState.IDLE:
                self.gain.state = PropertyState.OK

    async def request(self, camera: ICamera, vector: Property[Any], values: Values) -> Any:
        """A client's request: a coroutine to run as an action, or None when answered at once."""
        if vector is self.temperature and isinstance(camera, ICooling):
            return camera.set_cooling(True, float(values["CCD_TEMPERATURE_VALUE"]))
        if vector is self.cooler and isinstance(camera, ICooling):
            setpoint = (await camera.get_cooling()).setpoint
            return camera.set_cooling(bool(values.get("COOLER_ON")), setpoint)
        if vector is self.gain and isinstance(camera, IGain):
            return camera.set_gain(float(values["GAIN"]))
        if vector is self.compression:
            if values.get("CCD_COMPRESS"):
                raise InvalidArgumentError(f"{vector.where}: only CCD_RAW is offered (frames go as written)")
            return None
        if vector is self.upload_mode:
            if not values.get("UPLOAD_CLIENT"):
                raise InvalidArgumentError(
                    f"{vector.where}: only UPLOAD_CLIENT is offered (frames stay in nightcrew's archive)"
                )
            return None
        raise InvalidArgumentError(f"{vector.where} cannot be set")

    def read_frame(self, data: bytes, info: Property[NumberMember] | None) -> list[Property[Any]]:
        """Take the pixel size and colour pattern from a frame's FITS header; the vectors that changed."""
        try:
            header = fits.Header.fromstring(data[: 2880 * 20].decode("ascii", errors="replace"))
        except Exception:  # a file without a readable header changes nothing
            return []
        changed: list[Property[Any]] = []
        bayer = str(header.get("BAYERPAT", "")).strip()
        if bayer != self.cfa.by_name["CFA_TYPE"].value:
            self.cfa.by_name["CFA_TYPE"].value = bayer
            changed.append(self.cfa)
        size_x = _unbinned(header, "XPIXSZ", "XBINNING")
        size_y = _unbinned(header, "YPIXSZ", "YBINNING") or size_x
        if info is not None and size_x is not None:
            for key, value in (
                ("CCD_PIXEL_SIZE", size_x),
                ("CCD_PIXEL_SIZE_X", size_x),
                ("CCD_PIXEL_SIZE_Y", size_y),
            ):
                info.by_name[key].value = round(float(value or size_x), 4)
            changed.append(info)
        return changed


def _unbinned(header: Any, size_key: str, binning_key: str) -> float | None:
    size, binning = header.get(size_key), header.get(binning_key, 1)
    if not isinstance(size, (int, float)) or size <= 0:
        return None
    return float(size) / (float(binning) if isinstance(binning, (int, float)) and binning > 0 else 1.0)
