"""What cameras and spectrographs share: one exposure at a time, status, abort, headers, FITS files.

:meth:`ExposingModule._take_exposure` runs the whole sequence of one exposure:

1. refuse at once with DeviceBusyError if an exposure runs (before any await, so two calls in the
   same instant cannot both start);
2. ask every IFitsHeaderBefore peer for cards *concurrently* with the exposure;
3. expose through the driver's hook (abortable: the caller gets AbortedError); a driver that has
   work to do before the shutter opens calls :meth:`ExposingModule._start_integration` when it
   opens, so DATE-OBS and the progress count from then, not from the call. A driver that can end an
   exposure early and keep it (IStoppableExposure) waits with :meth:`ExposingModule._integrate`, or
   watches ``_stop_requested`` and reports the real time with :meth:`ExposingModule._cut_short`;
   the frame then says so (EXPTIME real, EXPREQ asked for, CUTSHORT = T);
4. ask IFitsHeaderAfter peers, await both header rounds (each peer bounded by ``header_timeout``);
5. merge cards (static config < peers < driver < the camera's own), write the FITS file through the
   VFS in one atomic write and announce it. A provider named in ``expect_headers_from`` that answers
   in neither round, or one that answered for an earlier frame but not for this one (down,
   restarting, failing), is named in the card ``HDRMISS``, and the log says so: no frame silently
   lacks a provider's cards, not even the first after the camera itself restarted.
"""

from __future__ import annotations

import asyncio
import logging
import math
from collections.abc import Awaitable, Callable, Mapping
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

import numpy as np
import numpy.typing as npt

from nightcrew.astro import modified_julian_date
from nightcrew.errors import (
    AbortedError,
    ConfigError,
    DeviceBusyError,
    GrabImageError,
    InvalidArgumentError,
    NightcrewError,
)
from nightcrew.events import ExposureStatusChangedEvent
from nightcrew.interfaces import ExposureStatus, FitsCard, FitsValue, IAbortable, IExposure, ModuleState
from nightcrew.interfaces.quantities import MAX_EXPOSURE_TIME, ExposureTime
from nightcrew.modules.camera.fitsfile import blocking_fits_bytes
from nightcrew.modules.camera.headers import HeaderReplies, MissingHeaders, ask_header_providers, clean_cards
from nightcrew.modules.module import Module
from nightcrew.timeout import wall_allowance
from nightcrew.vfs.filenames import check_filename_pattern, format_filename

__all__ = ["ExposingModule", "Frame"]

#: Clock seconds a frame may take beyond its exposure, read-out and header round: the devices a
#: driver asks before the shutter opens, writing the file.
EXPOSURE_MARGIN = 60.0
#: Clock seconds read-out and download may take, for drivers that do not say.
DEFAULT_READOUT_ALLOWANCE = 60.0

log = logging.getLogger(__name__)


@dataclass
class Frame:
    """What a driver's exposure hook returns: the data and the driver's own header cards."""

    data: npt.NDArray[Any]
    header: dict[str, FitsCard] = field(default_factory=dict)


class ExposingModule(Module, IAbortable, IExposure):
    """Base of modules that expose and write FITS files.

    Args:
        filename_pattern: VFS path of new files, with FITS keywords as placeholders.
        fits_headers: Fixed cards for every file, e.g. ``{INSTRUME: SimCam, OBSERVER: robot}``.
        header_timeout: Clock seconds each header provider may take before it is left out.
        expect_headers_from: Modules whose FITS cards every frame should carry (e.g. ``[telescope,
            filters]``); a frame without them names them in ``HDRMISS``, from the first frame on.
        max_exposure_time: The longest exposure ``set_exposure_time`` accepts, in seconds; a
            device that reports a shorter maximum (Alpaca ``ExposureMax``, INDI ``CCD_EXPOSURE``)
            lowers it further.
        **kwargs: Module options.
    """

    default_pattern = "/cache/{DATE-OBS}-{IMAGETYP}.fits"

    def __init__(
        self,
        *,
        filename_pattern: str | None = None,
        fits_headers: dict[str, FitsValue] | None = None,
        header_timeout: float = 5.0,
        expect_headers_from: list[str] | None = None,
        max_exposure_time: ExposureTime = 3600.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self._max_exposure_time = float(max_exposure_time)
        self._device_exposure_range = (0.0, MAX_EXPOSURE_TIME)
        self._filename_pattern = filename_pattern or self.default_pattern
        check_filename_pattern(self._filename_pattern)
        if not header_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {header_timeout}", key="header_timeout")
        static = {key: (value, "") for key, value in (fits_headers or {}).items()}
        self._static_cards = clean_cards(static, "fits_headers")
        if len(self._static_cards) != len(static):
            bad = sorted(set(static) - set(self._static_cards))
            raise ConfigError(f"invalid FITS keywords or values: {', '.join(bad)}", key="fits_headers")
        self._header_timeout = float(header_timeout)
        self._missing_headers = MissingHeaders(self._check_expected_providers(expect_headers_from))
        self._exposure_status = ExposureStatus.IDLE
        self._busy = False
        self._exposure_task: asyncio.Task[Frame] | None = None
        self._aborted = False
        self._exposure_start = 0.0
        self._exposure_length = 0.0
        self._stop_requested = asyncio.Event()
        self._exposed_until_stop: float | None = None

    def _set_device_exposure_range(self, low: float, high: float) -> None:
        """Drivers call this with the range the device reports when they connect."""
        if not (math.isfinite(low) and math.isfinite(high) and 0 <= low <= high and high > 0):
            log.warning("%s: ignoring the device's exposure range %r..%r s", self.name, low, high)
            return
        self._device_exposure_range = (float(low), float(high))

    def _checked_exposure_time(self, exposure_time: float) -> float:
        """``exposure_time`` as float if this camera can take it: 0 (a bias) or within the device's
        range and at most ``max_exposure_time``; otherwise InvalidArgumentError naming the range."""
        low, device_high = self._device_exposure_range
        high = min(device_high, self._max_exposure_time)
        if math.isfinite(exposure_time) and (exposure_time == 0 or low <= exposure_time <= high):
            return float(exposure_time)
        limit = "max_exposure_time" if self._max_exposure_time <= device_high else "the device's maximum"
        allowed = f"0..{high:g} s" if low == 0 else f"0 or {low:g}..{high:g} s"
        raise InvalidArgumentError(
            f"exposure_time {exposure_time!r} s is out of range for {self.name}: {allowed} "
            f"(the maximum is {limit})"
        )

    def _check_expected_providers(self, names: list[str] | None) -> set[str]:
        if names is None:
            return set()
        if not all(names):
            raise ConfigError(f"an empty module name in {names}", key="expect_headers_from")
        if len(set(names)) != len(names):
            raise ConfigError(f"names a module twice: {names}", key="expect_headers_from")
        if self.name in names:
            raise ConfigError(f"{self.name} cannot provide headers to itself", key="expect_headers_from")
        return set(names)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.send_event(ExposureStatusChangedEvent(last=None, current=self._exposure_status))

    # --- the announced timeout -----------------------------------------------------------------

    def _hw_readout_allowance(self) -> float:
        """Clock seconds reading out and downloading one frame may take (part of the announced
        timeout of an exposure); drivers that know their read-out say so."""
        return DEFAULT_READOUT_ALLOWANCE

    def _exposure_timeout(self, exposure_time: float) -> float:
        """The timeout an exposure of ``exposure_time`` s announces: that, plus the read-out
        allowance, the header round (``header_timeout``), a margin (:data:`EXPOSURE_MARGIN`) and
        the wall allowance (:func:`~nightcrew.timeout.wall_allowance`), in clock seconds."""
        readout = self._hw_readout_allowance() + self._header_timeout
        return exposure_time + readout + EXPOSURE_MARGIN + wall_allowance(self.clock.speed)

    # --- status --------------------------------------------------------------------------------

    async def _set_exposure_status(self, status: ExposureStatus) -> None:
        """Change the exposure status and tell the others (drivers call this for READOUT)."""
        if status is self._exposure_status:
            return
        last, self._exposure_status = self._exposure_status, status
        if self.comm.is_open:
            await self.comm.send_event(ExposureStatusChangedEvent(last=last, current=status))

    async def get_exposure_status(self) -> ExposureStatus:
        return self._exposure_status

    async def get_exposure_progress(self) -> float:
        if self._exposure_status is ExposureStatus.IDLE:
            return 0.0
        if self._exposure_length <= 0:
            return 100.0
        return min(100.0, 100.0 * (self.clock.time() - self._exposure_start) / self._exposure_length)

    def _exposure_time_left(self) -> float:
        if self._exposure_status is not ExposureStatus.EXPOSING:
            return 0.0
        return max(0.0, self._exposure_start + self._exposure_length - self.clock.time())

    async def abort(self) -> None:
        task = self._exposure_task
        if task is not None and not task.done():
            log.info("%s: aborting exposure", self.name)
            self._aborted = True
            task.cancel()
            await asyncio.wait([task])

    async def stop_exposure(self) -> None:
        """IStoppableExposure, for the subclasses that declare it (their drivers honour the request)."""
        if self._exposure_status is ExposureStatus.EXPOSING and not self._stop_requested.is_set():
            log.info("%s: stopping the exposure early; the frame is read out and kept", self.name)
            self._stop_requested.set()

    async def _integrate(self, exposure_time: float) -> float:
        """Let the shutter stay open ``exposure_time`` clock seconds or until :meth:`stop_exposure`;
        the seconds it was open (drivers that time the exposure themselves call this)."""
        try:
            async with self.clock.timeout(exposure_time):
                await self._stop_requested.wait()
        except TimeoutError:
            return exposure_time
        return self._cut_short(self.clock.time() - self._exposure_start)

    def _cut_short(self, exposed: float) -> float:
        """The exposure was stopped after ``exposed`` seconds: the frame's EXPTIME says so."""
        self._exposed_until_stop = max(0.0, min(exposed, self._exposure_length))
        return self._exposed_until_stop

    def _cut_short_cards(self, asked: float) -> dict[str, FitsCard]:
        exposed = self._exposed_until_stop
        if exposed is None:
            return {}
        return {
            "EXPTIME": (exposed, "Exposure time [s], cut short"),
            "EXPREQ": (asked, "Exposure time asked for [s]"),
            "CUTSHORT": (True, "Exposure stopped early (e.g. bad weather), frame kept"),
        }

    # --- the exposure --------------------------------------------------------------------------

    def _check_not_busy(self) -> None:
        if self._busy:
            raise DeviceBusyError(f"{self.name} is already exposing; wait for the frame or abort()")

    async def _take_exposure(
        self,
        expose: Callable[[], Awaitable[Frame]],
        exposure_time: float,
        own_cards: Callable[[Frame], dict[str, FitsCard]],
        announce: Callable[[str], Awaitable[None]] | None,
    ) -> str:
        """Run one exposure (see the module docstring) and return the file's VFS path.

        Args:
            expose: Starts the driver's exposure and returns its frame.
            exposure_time: Seconds, for progress and EXPTIME.
            own_cards: The module's cards for the frame (checked and added last).
            announce: Sends the new-file event with the path; None for no event.
        """
        self._check_not_busy()
        self._busy = True
        self._aborted = False
        self._stop_requested.clear()
        self._exposed_until_stop = None
        before = asyncio.create_task(self._headers("before"))
        after: asyncio.Task[HeaderReplies] | None = None
        try:
            self._exposure_start, self._exposure_length = self.clock.time(), exposure_time
            await self._set_exposure_status(ExposureStatus.EXPOSING)
            frame = await self._run_hook(expose)
            after = asyncio.create_task(self._headers("after"))
            before_replies, after_replies = await before, await after
            missing = self._missing_headers.missing(before_replies, after_replies)
            cards = {
                **self._static_cards,
                **before_replies.cards,
                **after_replies.cards,
                **MissingHeaders.card(missing),
                **clean_cards(frame.header, "driver"),
                **_time_cards(self._exposure_start),
            }
            cards.update(own_cards(frame))
            cards.update(self._cut_short_cards(exposure_time))
            exposed = cards["EXPTIME"][0] if "EXPTIME" in cards else None
            cards.update(_end_cards(self._exposure_start, exposed))
            filename = format_filename(self._filename_pattern, {k: v for k, (v, _) in cards.items()})
            await self._write(filename, frame.data, cards)
        finally:
            for task in (before, after):
                if task is not None and not task.done():
                    task.cancel()
            self._busy = False
            self._exposure_task = None
            await self._set_exposure_status(ExposureStatus.IDLE)
        if missing:
            log.warning(
                "%s: wrote %s without the headers of %s", self.name, filename, ", ".join(sorted(missing))
            )
        else:
            log.info("%s: wrote %s", self.name, filename)
        if announce is not None:
            await announce(filename)
        return filename

    def _start_integration(self) -> float:
        """Drivers call this when the shutter opens (a dark: when integration begins); returns the
        clock time, which becomes DATE-OBS. Without the call the exposure starts when the hook is
        called, before whatever the driver asks or sets up first."""
        self._exposure_start = self.clock.time()
        return self._exposure_start

    async def _run_hook(self, expose: Callable[[], Awaitable[Frame]]) -> Frame:
        async def run() -> Frame:
            return await expose()

        self._exposure_task = asyncio.create_task(run())
        try:
            frame = await self._exposure_task
        except asyncio.CancelledError:
            current = asyncio.current_task()
            if self._aborted and not (current and current.cancelling()):
                raise AbortedError("exposure aborted") from None
            raise
        except NightcrewError:
            raise
        except Exception as exc:
            raise GrabImageError(f"exposure failed: {type(exc).__name__}: {exc}") from exc
        if not isinstance(frame, Frame) or not isinstance(frame.data, np.ndarray):
            raise GrabImageError(f"driver returned {type(frame).__name__}, expected a Frame with an array")
        return frame

    async def _headers(self, when: str) -> HeaderReplies:
        return await ask_header_providers(self.comm, when, self._header_timeout)

    async def _write(self, filename: str, data: npt.NDArray[Any], cards: Mapping[str, FitsCard]) -> None:
        # Serialising takes tens of milliseconds: in a thread, so the event loop (guiding, the
        # mastermind, on a fast clock the clock itself) does not stall on every frame.
        # Writing costs what it costs at a telescope, not clock-speed times as much: see Clock.work.
        try:
            async with self.clock.work("write_frame"):
                payload = await asyncio.to_thread(blocking_fits_bytes, data, cards)
                await self.vfs.write_bytes(filename, payload)
        except (NightcrewError, ValueError) as exc:
            raise GrabImageError(f"cannot write {filename}: {exc}") from exc


def _end_cards(start: float, exposed: object) -> dict[str, FitsCard]:
    """DATE-END: the start plus the seconds the frame really integrated (EXPTIME, cut short or not)."""
    if not isinstance(exposed, int | float) or isinstance(exposed, bool):
        return {}
    end = datetime.fromtimestamp(start + float(exposed), UTC)
    return {"DATE-END": (end.strftime("%Y-%m-%dT%H:%M:%S.%f")[:-3], "UTC end of exposure")}


def _time_cards(unix_time: float) -> dict[str, FitsCard]:
    start = datetime.fromtimestamp(unix_time, UTC)
    mjd = modified_julian_date(unix_time)
    return {
        "DATE-OBS": (start.strftime("%Y-%m-%dT%H:%M:%S.%f")[:-3], "UTC start of exposure"),
        "MJD-OBS": (round(mjd, 8), "Modified Julian date of start of exposure"),
        "ORIGIN": ("nightcrew", "Software that wrote this file"),
    }
