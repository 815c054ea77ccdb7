"""A CCD behind an INDI driver: exposure, binning, frame, frame type, temperature, gain; the image
arrives as a FITS BLOB (``CCD1``) and becomes nightcrew's FITS file with nightcrew's headers.

An exposure sets ``CCD_FRAME``, ``CCD_BINNING`` and ``CCD_FRAME_TYPE``, starts ``CCD_EXPOSURE``
and waits for the vector to leave Busy and for a new ``CCD1`` BLOB (``UPLOAD_MODE`` is set to
client upload, ``CCD_TRANSFER_FORMAT`` to FITS). The driver's FITS is read for its pixels and a
few camera cards (:data:`DRIVER_CARDS`); the file nightcrew writes is built by the camera base,
so its headers are nightcrew's (telescope, filter, focus, weather ... from the header providers)
and nothing is half-written when the BLOB is bad. ``compress: true`` asks the driver for
zlib-compressed BLOBs (``CCD_COMPRESSION``), which the client inflates.

On every (re)connection, before the module is ready, an exposure the driver still runs
(``CCD_EXPOSURE`` Busy, e.g. started by a camera module that was killed) is aborted
(``CCD_ABORT_EXPOSURE``), so the next exposure does not find the camera busy, and cooling this
module had switched on is switched on again at its set point.

Example (``examples/indi/camera.yaml``)::

    class: nightcrew.modules.indi.IndiCamera
    host: 192.168.1.20
    device: CCD Simulator
    gain: 90
"""

from __future__ import annotations

import asyncio
import io
import logging
from typing import Any

import numpy as np

from nightcrew.bridges.indi import Blob, IndiError, PropertyState, Vector
from nightcrew.errors import ConfigError, GrabImageError, NotSupportedError
from nightcrew.interfaces import Binning, ExposureStatus, FitsCard, ImageType, Window
from nightcrew.modules.camera import BaseCamera, ExposureSettings, Frame
from nightcrew.modules.indi.link import IndiModule

__all__ = ["DRIVER_CARDS", "IndiCamera", "blocking_read_fits", "fits_frame", "plain_fits_frame"]

log = logging.getLogger(__name__)

#: Cards of the driver's FITS header that describe the camera and go into nightcrew's file.
DRIVER_CARDS = ("INSTRUME", "CCD-TEMP", "PIXSIZE1", "PIXSIZE2", "XPIXSZ", "YPIXSZ", "GAIN", "OFFSET")

_FRAME_TYPES = {
    ImageType.BIAS: "FRAME_BIAS",
    ImageType.DARK: "FRAME_DARK",
    ImageType.SKYFLAT: "FRAME_FLAT",
    ImageType.DOMEFLAT: "FRAME_FLAT",
}
#: Until the device told its chip size (the base asks for it at construction).
_NO_CHIP = Window(0, 0, 1, 1)


#: FITS header blocks and the cards a plain 16-bit image's header must have for the fast read.
_BLOCK = 2880
_MAX_HEADER_BLOCKS = 100
_PLAIN = {"SIMPLE": True, "BITPIX": 16, "NAXIS": 2}


async def fits_frame(blob: Blob, device: str) -> Frame:
    """Pixels and camera cards of a FITS BLOB: a plain 16-bit image at once (a copy of its pixels,
    well under a millisecond a megapixel), anything else (fpack, other types) read by astropy in a
    thread. Under load, the thread hop cost more than the reading (bench/indi.py)."""
    frame = plain_fits_frame(blob, device)
    return frame if frame is not None else await asyncio.to_thread(blocking_read_fits, blob, device)


def plain_fits_frame(blob: Blob, device: str) -> Frame | None:
    """A single-HDU 16-bit image with BZERO 0 or 32768 (what INDI's CCD drivers send); else None."""
    from astropy.io import fits  # type: ignore[import-untyped]

    data = blob.data
    if blob.format.lower() not in (".fits", ".fit", ".fts") or not data.startswith(b"SIMPLE  ="):
        return None
    blocks = range(0, min(len(data), _MAX_HEADER_BLOCKS * _BLOCK), _BLOCK)
    end = next((i for i in blocks if b"END     " in _cards_ending(data, i)), -1)
    if end < 0:
        return None
    try:
        header = fits.Header.fromstring(data[: end + _BLOCK])
    except (ValueError, TypeError):
        return None  # let astropy's full reader name the problem
    plain = all(header.get(key) == value for key, value in _PLAIN.items())
    if not plain or header.get("BSCALE", 1) != 1 or header.get("BZERO", 0) not in (0, 32768):
        return None
    width, height = header.get("NAXIS1"), header.get("NAXIS2")
    if not isinstance(width, int) or not isinstance(height, int) or width < 1 or height < 1:
        return None
    if len(data) < end + _BLOCK + 2 * width * height:
        raise IndiError(
            f"BLOB is not a readable FITS file: {width}x{height} pixels announced, the data is shorter",
            device=device,
            name="CCD1",
        )
    # Byte order first (one fast copy), then the sign bit in place: twenty times faster than
    # working on the big-endian array.
    pixels = np.frombuffer(data, dtype=">u2", count=width * height, offset=end + _BLOCK).astype(np.uint16)
    if header.get("BZERO", 0) == 32768:
        pixels ^= np.uint16(0x8000)  # stored signed, offset by 2**15
    elif pixels.size and pixels.max() > 0x7FFF:  # negative as int16
        raise IndiError("pixels outside 0..65535 (int16)", device=device, name="CCD1")
    cards: dict[str, FitsCard] = {
        key: (header[key], header.comments[key]) for key in DRIVER_CARDS if key in header
    }
    return Frame(pixels.reshape(height, width), cards)


def _cards_ending(data: bytes, block: int) -> list[bytes]:
    return [data[at : at + 8] for at in range(block, min(block + _BLOCK, len(data)), 80)]


def blocking_read_fits(blob: Blob, device: str) -> Frame:
    """Pixels (uint16) and camera cards of a FITS BLOB; parsing takes milliseconds: run in a thread."""
    from astropy.io import fits

    if blob.format.lower() not in (".fits", ".fit", ".fts", ".fits.fz"):
        raise IndiError(
            f"BLOB format {blob.format!r} is not FITS (set CCD_TRANSFER_FORMAT to FITS)",
            device=device,
            name="CCD1",
        )
    try:
        with fits.open(io.BytesIO(blob.data)) as hdus:
            # fpack (.fits.fz, what CCD_COMPRESSION gives) keeps the image in the first extension.
            hdu = next((h for h in hdus if h.data is not None), hdus[0])
            data = np.asarray(hdu.data)
            header = hdu.header
            cards: dict[str, FitsCard] = {
                key: (header[key], header.comments[key]) for key in DRIVER_CARDS if key in header
            }
    except (OSError, ValueError, TypeError, IndexError) as exc:
        raise IndiError(f"BLOB is not a readable FITS file: {exc}", device=device, name="CCD1") from exc
    if data.ndim != 2:
        raise IndiError(f"expected a 2-D image, got shape {data.shape}", device=device, name="CCD1")
    if data.dtype != np.uint16:
        if data.size and (data.min() < 0 or data.max() > 65535):
            raise IndiError(f"pixels outside 0..65535 ({data.dtype})", device=device, name="CCD1")
        data = data.astype(np.uint16)
    return Frame(data, cards)


class IndiCamera(IndiModule, BaseCamera):
    """An INDI CCD.

    Args:
        gain: Gain to set on every connection (CCD_GAIN); None leaves the driver's.
        compress: Ask for compressed BLOBs (CCD_COMPRESSION).
        readout_timeout: Wall seconds from the end of the exposure to the image's arrival.
        **kwargs: INDI options (``host``, ``port``, ``device`` ...) and camera options.
    """

    indi_needs = ("CCD_EXPOSURE", "CCD1", "CCD_INFO", "CCD_FRAME", "CCD_BINNING")
    indi_blobs = True
    _chip = _NO_CHIP

    def __init__(
        self,
        *,
        gain: float | None = None,
        compress: bool = False,
        readout_timeout: float = 60.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not readout_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {readout_timeout}", key="readout_timeout")
        self._gain = gain
        self._compress = bool(compress)
        self._readout_timeout = float(readout_timeout)
        self._max_binning = 1

    # --- connection ----------------------------------------------------------------------------

    async def _on_indi_ready(self) -> None:
        indi, wait = self._indi, self._indi.connect_timeout
        # Drivers fill in the chip size only after CONNECT: wait for a real one.
        info = await indi.client.wait(
            indi.device,
            "CCD_INFO",
            lambda v: v.number("CCD_MAX_X") >= 1 and v.number("CCD_MAX_Y") >= 1,
            wait,
            "a chip size",
        )
        chip = Window(0, 0, round(info.number("CCD_MAX_X")), round(info.number("CCD_MAX_Y")))
        if self._window in (_NO_CHIP, self._chip) or chip != self._chip:
            self._window = chip
        self._chip = chip
        binning = indi.vector("CCD_BINNING")
        self._max_binning = max(1, round(binning.limits.get("HOR_BIN", (1, 1, 1))[1]))
        exposure_limits = indi.vector("CCD_EXPOSURE").limits.get("CCD_EXPOSURE_VALUE")
        if exposure_limits is not None:
            self._set_device_exposure_range(exposure_limits[0], exposure_limits[1])
        if indi.has("UPLOAD_MODE"):
            await indi.switch("UPLOAD_MODE", "UPLOAD_CLIENT", wait=wait)
        if indi.has("CCD_TRANSFER_FORMAT"):
            await indi.switch("CCD_TRANSFER_FORMAT", "FORMAT_FITS", wait=wait)
        if indi.has("CCD_COMPRESSION"):
            await indi.switch(
                "CCD_COMPRESSION", "INDI_ENABLED" if self._compress else "INDI_DISABLED", wait=wait
            )
        if self._gain is not None:
            await self._send_gain(self._gain)
        if not self._busy and indi.is_busy("CCD_EXPOSURE"):  # not ours: ours fails by itself
            log.warning("%s: %s is still exposing: aborting it", self.name, indi.where)
            await self._abort_exposure()
            await indi.client.wait(
                indi.device, "CCD_EXPOSURE", lambda v: v.state is not PropertyState.BUSY, wait, "the abort"
            )
        await self._restore_cooling()  # a restarted driver comes back with its cooler off

    async def _send_gain(self, gain: float) -> None:
        if not self._indi.has("CCD_GAIN"):
            raise NotSupportedError(f"{self._indi.where} has no gain (CCD_GAIN)")
        await self._indi.send("CCD_GAIN", {"GAIN": gain}, wait=self._indi.connect_timeout)

    # --- hooks ---------------------------------------------------------------------------------

    def _hw_readout_allowance(self) -> float:
        return 2 * self._readout_timeout  # the exposure's end, then the BLOB's arrival

    def _hw_full_frame(self) -> Window:
        return self._chip

    def _hw_binnings(self) -> list[Binning]:
        return [Binning(n, n) for n in range(1, self._max_binning + 1)]

    async def _hw_expose(self, settings: ExposureSettings) -> Frame:
        indi, wait = self._indi, self._indi.connect_timeout
        window, binning = settings.window, settings.binning
        await indi.send(
            "CCD_FRAME",
            {"X": window.left, "Y": window.top, "WIDTH": window.width, "HEIGHT": window.height},
            wait=wait,
        )
        await indi.send("CCD_BINNING", {"HOR_BIN": binning.x, "VER_BIN": binning.y}, wait=wait)
        if indi.has("CCD_FRAME_TYPE"):
            await indi.switch(
                "CCD_FRAME_TYPE", _FRAME_TYPES.get(settings.image_type, "FRAME_LIGHT"), wait=wait
            )
        blob_before = indi.vector("CCD1").generation
        self._start_integration()
        try:
            await indi.send(
                "CCD_EXPOSURE",
                {"CCD_EXPOSURE_VALUE": settings.exposure_time},
                wait=settings.exposure_time + self._readout_timeout,
            )
            await self._set_exposure_status(ExposureStatus.READOUT)
            image = await indi.client.wait(
                indi.device,
                "CCD1",
                lambda v: v.generation > blob_before,
                self._readout_timeout,
                "a new image",
            )
        except asyncio.CancelledError:
            await self._abort_exposure()
            raise
        frame = await fits_frame(_first_blob(image), indi.device)
        if frame.data.shape != settings.shape:
            raise GrabImageError(
                f"{indi.where}: CCD1 holds a {frame.data.shape} image, expected {settings.shape}"
            )
        return frame

    async def _abort_exposure(self) -> None:
        if self._indi.readable and self._indi.has("CCD_ABORT_EXPOSURE"):
            try:
                await self._indi.send("CCD_ABORT_EXPOSURE", {"ABORT": True})
            except IndiError as exc:
                log.warning("%s: aborting the exposure failed: %s", self.name, exc)

    async def _hw_set_cooling(self, enabled: bool, setpoint: float) -> None:
        if not self._indi.has("CCD_TEMPERATURE"):
            raise NotSupportedError(f"{self._indi.where} has no cooling (CCD_TEMPERATURE)")
        # The driver ramps to the setpoint, its cooler and temperature Busy until there (the
        # simulator's for minutes): do not wait for that.
        if self._indi.has("CCD_COOLER"):
            await self._indi.switch("CCD_COOLER", "COOLER_ON" if enabled else "COOLER_OFF")
        if enabled:
            await self._indi.send("CCD_TEMPERATURE", {"CCD_TEMPERATURE_VALUE": setpoint})

    async def _hw_cooling_power(self) -> float:
        if self._indi.has("CCD_COOLER_POWER"):
            vector = self._indi.vector("CCD_COOLER_POWER")
            return next(iter(v for v in vector.members.values() if isinstance(v, float)), 0.0)
        return 0.0

    async def _hw_ccd_temperature(self) -> float | None:
        if self._indi.readable and self._indi.has("CCD_TEMPERATURE"):
            return self._indi.vector("CCD_TEMPERATURE").number("CCD_TEMPERATURE_VALUE")
        return None

    # --- run-time configuration ----------------------------------------------------------------

    def _get_config_gain(self) -> float:
        return self._indi.vector("CCD_GAIN").number("GAIN")

    async def _set_config_gain(self, value: float) -> None:
        await self._send_gain(float(value))
        self._gain = float(value)


def _first_blob(vector: Vector) -> Blob:
    for value in vector.members.values():
        if isinstance(value, Blob):
            return value
    raise IndiError("holds no BLOB", device=vector.device, name=vector.name)
