"""Auto-guiding: keep the stars where they were on the reference frame.

The ``pipeline`` ends in a reference offsets processor (NStarOffsets, ProjectedOffsets): the first
frame after start, a target change or a reset becomes the reference; every later frame gives the
pointing error against it. The correction is ``gain`` times the error, at most ``max_correction``
arcsec per step. Frames are skipped — no correction, a warning, state LOST — when they show no
stars or fail to process (clouds), or when their error exceeds ``max_error`` (a glitch, a bumped
telescope); after ``max_bad_frames`` in a row the reference is taken anew.

A target change makes the old reference useless: a MoveRaDecEvent from the ``telescope``, a
change of the header's OBJECT, or of the target position (RA/DEC minus the telescope's
RAOFF/DECOFF) by more than ``retarget_distance`` restarts with a new reference.

On a German-equatorial mount the field turns by 180° on the sky when the mount flips to the other
side of its pier, so a guider that turns pixel offsets into sky directions by its configured
``position_angle`` (frames without a WCS) would push the wrong way afterwards. With ``pier_side``
(the side ``position_angle`` was measured on) every new reference reads the mount's side and
turns the angle by 180° on the other side (:func:`position_angle_on_side`): the calibration
follows the flip. Frames with a WCS need nothing: their offsets are on the sky already.

State and quality are published: :meth:`get_loop_state`, the readable config value ``rms``
(``get_config_value("rms")``, arcsec, over the last ``rms_frames`` frames), and the FITS cards
``GUIDING`` (loop state) and ``GUIDRMS`` (arcsec) given to every camera (IFitsHeaderBefore).

:class:`AutoGuiding` exposes a guide camera in a loop; :class:`ScienceFrameAutoGuiding` guides on
the frames a science camera announces with NewImageEvent.
"""

from __future__ import annotations

import asyncio
import logging
import math
from collections import deque
from typing import Any

from nightcrew.astro import angular_separation
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import MoveRaDecEvent, NewImageEvent
from nightcrew.images import Image, ImageProcessor
from nightcrew.images.processors.offsets import OFFSETS_KEY, Offsets
from nightcrew.interfaces import (
    FitsCard,
    IAutoGuiding,
    ICamera,
    IExposureTime,
    IFitsHeaderBefore,
    ImageType,
    IPierSide,
    LoopState,
    PierSide,
)
from nightcrew.interfaces.quantities import ExposureTime
from nightcrew.modules.module import Module
from nightcrew.modules.pointing.apply import ApplyOffsets, ApplyRaDecOffsets, SkyError, sky_error

__all__ = ["AutoGuiding", "BaseGuiding", "ScienceFrameAutoGuiding", "position_angle_on_side"]

log = logging.getLogger(__name__)


def position_angle_on_side(position_angle: float, calibrated_side: PierSide, side: PierSide) -> float:
    """The detector's position angle (degrees, 0..360) with the mount on ``side``, when it is
    ``position_angle`` on ``calibrated_side``: a flip to the other side of the pier turns the field
    half round (east and north both reverse on the detector). A side that is unknown keeps it."""
    flipped = PierSide.UNKNOWN not in (calibrated_side, side) and side is not calibrated_side
    return (position_angle + (180.0 if flipped else 0.0)) % 360.0


class BaseGuiding(Module, IAutoGuiding, IFitsHeaderBefore):
    """The guiding loop's logic; subclasses decide where frames come from.

    Args:
        pipeline: Image processors ending in a reference offsets processor.
        telescope: The telescope (for the default ``apply`` and its MoveRaDecEvents).
        apply: How corrections reach the telescope; default ``ApplyRaDecOffsets(telescope)``.
        exposure_time: Seconds per guide frame (AutoGuiding).
        gain: Fraction of the measured error corrected per frame (0..1].
        max_correction: Largest correction per frame (arcsec); larger ones are clipped.
        max_error: Frames with a larger error are skipped (arcsec).
        max_bad_frames: Consecutive bad frames after which a new reference is taken.
        retarget_distance: Target moves larger than this (arcsec) need a new reference.
        rms_frames: Number of recent frames the RMS is taken over.
        position_angle: Detector orientation for frames without a WCS (see pixel_error_to_sky).
        flip: East is +x on the detector.
        pier_side: ``east`` or ``west``: the side of a German-equatorial mount's pier on which
            ``position_angle`` holds; on the other side it is turned by 180°. None: the same on
            either side (a mount without sides, or frames with a WCS).
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        pipeline: ImageProcessor,
        telescope: str = "telescope",
        apply: ApplyOffsets | None = None,
        exposure_time: ExposureTime = 5.0,
        gain: float = 0.7,
        max_correction: float = 5.0,
        max_error: float = 30.0,
        max_bad_frames: int = 5,
        retarget_distance: float = 60.0,
        rms_frames: int = 20,
        position_angle: float = 0.0,
        flip: bool = False,
        pier_side: str | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if pier_side is not None and pier_side not in (PierSide.EAST, PierSide.WEST):
            raise ConfigError(f"must be east or west, got {pier_side!r}", key="pier_side")
        if not 0 < gain <= 1:
            raise ConfigError(f"must be within (0, 1], got {gain}", key="gain")
        if not (max_correction > 0 and max_error > 0 and retarget_distance > 0):
            raise ConfigError("max_correction, max_error and retarget_distance must be > 0", key="max_error")
        if max_bad_frames < 1 or rms_frames < 1 or not exposure_time >= 0:
            raise ConfigError("max_bad_frames, rms_frames >= 1 and exposure_time >= 0", key="max_bad_frames")
        self._pipeline = self.add_child(pipeline)
        self._telescope = telescope
        self._apply = self.add_child(apply or ApplyRaDecOffsets(telescope))
        self._exposure_time = float(exposure_time)
        self._gain, self._max_correction, self._max_error = (
            float(gain),
            float(max_correction),
            float(max_error),
        )
        self._max_bad_frames, self._retarget_distance = max_bad_frames, float(retarget_distance)
        self._position_angle, self._flip = float(position_angle), flip
        self._calibrated_side = None if pier_side is None else PierSide(pier_side)
        self._angle_now = self._position_angle  # position_angle on the mount's side now
        self._errors: deque[float] = deque(maxlen=rms_frames)
        self._loop_state = LoopState.STOPPED
        self._bad_frames = 0
        self._target: tuple[str | None, float, float] | None = None  # OBJECT, RA, Dec of the reference
        self._expected: tuple[float, float] | None = None  # the new target after a MoveRaDecEvent
        # Bumped by stop() and every new reference: a frame whose analysis began before must not
        # correct the telescope afterwards (it may already be slewing to the next target).
        self._generation = 0

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(MoveRaDecEvent, self.on_move_radec)

    # --- IAutoGuiding --------------------------------------------------------------------------

    async def start(self) -> None:
        if self._loop_state is LoopState.STOPPED:
            await self._new_reference("guiding started")

    async def stop(self) -> None:
        self._loop_state = LoopState.STOPPED
        self._generation += 1
        log.info("%s: guiding stopped", self.name)

    async def is_running(self) -> bool:
        return self._loop_state is not LoopState.STOPPED

    async def get_loop_state(self) -> LoopState:
        return self._loop_state

    async def set_exposure_time(self, exposure_time: float) -> None:
        if not (math.isfinite(exposure_time) and exposure_time >= 0):
            raise ConfigError(f"exposure time must be >= 0 s, got {exposure_time}")
        self._exposure_time = float(exposure_time)

    async def get_exposure_time(self) -> float:
        return self._exposure_time

    async def get_exposure_time_left(self) -> float:
        return 0.0

    # --- published quality ---------------------------------------------------------------------

    @property
    def rms(self) -> float | None:
        """RMS (arcsec) of the measured error over the recent frames; None before any."""
        return math.sqrt(sum(e * e for e in self._errors) / len(self._errors)) if self._errors else None

    def _get_config_rms(self) -> float | None:
        return self.rms

    def _get_config_gain(self) -> float:
        return self._gain

    def _set_config_gain(self, value: float) -> None:
        if not 0 < value <= 1:
            raise ConfigError(f"gain must be within (0, 1], got {value}")
        self._gain = float(value)

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        cards: dict[str, FitsCard] = {"GUIDING": (self._loop_state.value, "Auto-guiding loop state")}
        rms = self.rms
        if rms is not None and self._loop_state is not LoopState.STOPPED:
            cards["GUIDRMS"] = (round(rms, 3), "Guiding error RMS, recent frames [arcsec]")
        return cards

    # --- the loop ------------------------------------------------------------------------------

    async def on_move_radec(self, event: MoveRaDecEvent, sender: str) -> bool:
        if sender == self._telescope and self._loop_state is not LoopState.STOPPED:
            await self._new_reference(f"telescope moved to {event.ra:.4f}, {event.dec:.4f}")
            self._expected = (event.ra, event.dec)
        return True

    async def _new_reference(self, reason: str) -> None:
        self._generation += 1
        await self._pipeline.reset()
        self._errors.clear()
        self._bad_frames, self._target = 0, None
        self._loop_state = LoopState.ACQUIRING
        await self._follow_pier_side()
        log.info("%s: waiting for a new reference frame (%s)", self.name, reason)

    async def _follow_pier_side(self) -> None:
        """Turn the detector's angle to the mount's pier side now (``pier_side`` configured)."""
        if self._calibrated_side is None:
            return
        telescope = await self.proxy(self._telescope, IPierSide)
        angle = position_angle_on_side(
            self._position_angle, self._calibrated_side, await telescope.get_pier_side()
        )
        if angle != self._angle_now:
            log.info("%s: pier side changed, guiding with the field at %.1f°", self.name, angle)
        self._angle_now = angle

    async def process_frame(self, image: Image) -> SkyError | None:
        """One step of the loop; returns the measured error, None for a reference or a skipped frame."""
        if self._loop_state is LoopState.STOPPED:
            return None
        target = _target_of(image)
        if self._expected is not None and target is not None:
            # A frame exposed before the telescope moved must not become the new reference.
            if angular_separation(*self._expected, *target[1:]) * 3600.0 > self._retarget_distance:
                log.debug("%s: skipping a frame of the previous target", self.name)
                return None
            self._expected = None
        if self._target is not None and _moved(self._target, target, self._retarget_distance):
            await self._new_reference(f"target changed to {target}")
        generation = self._generation
        try:
            image = await self._pipeline(image)
            offsets = image.metadata.get(OFFSETS_KEY)
            if not isinstance(offsets, Offsets):
                raise ConfigError("the guiding pipeline gave no offsets (end it with an offsets step)")
            error = sky_error(offsets, image, position_angle=self._angle_now, flip=self._flip)
        except NightcrewError as exc:
            await self._bad_frame(f"frame not usable: {exc}")
            return None
        if generation != self._generation:
            log.debug("%s: guiding stopped or re-referenced while a frame was analysed; dropped", self.name)
            return None
        if offsets.is_reference:
            self._loop_state, self._target, self._bad_frames = LoopState.CLOSED, target, 0
            log.info("%s: new reference frame, loop closed", self.name)
            return None
        if error.distance > self._max_error:
            await self._bad_frame(f'error {error.distance:.1f}" above max_error {self._max_error:g}"')
            return None
        self._errors.append(error.distance)
        self._bad_frames, self._loop_state = 0, LoopState.CLOSED
        correction = error.scaled(self._gain).limited(self._max_correction)
        await self._apply.apply(correction)
        log.debug('%s: error %.2f", corrected %.2f"', self.name, error.distance, correction.distance)
        return error

    async def _bad_frame(self, why: str) -> None:
        self._bad_frames += 1
        log.warning("%s: skipping a guide frame (%d in a row): %s", self.name, self._bad_frames, why)
        if self._bad_frames >= self._max_bad_frames:
            await self._new_reference(f"{self._bad_frames} bad frames in a row")
        elif self._loop_state is LoopState.CLOSED:
            self._loop_state = LoopState.LOST


class AutoGuiding(BaseGuiding):
    """Guides with a dedicated guide camera, exposing in a loop while started.

    Args:
        camera: The guide camera (ICamera; IExposureTime used if offered).
        **kwargs: See :class:`BaseGuiding`.
    """

    def __init__(self, *, camera: str | ICamera, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._camera = camera
        self._loop_task: asyncio.Task[None] | None = None

    async def start(self) -> None:
        await super().start()
        if self._loop_task is None or self._loop_task.done():
            self._loop_task = asyncio.get_running_loop().create_task(self._guide_loop(), name="guiding")

    async def stop(self) -> None:
        await super().stop()
        task, self._loop_task = self._loop_task, None
        if task is not None:
            task.cancel()
            await asyncio.gather(task, return_exceptions=True)

    async def close(self) -> None:
        await self.stop()
        await super().close()

    async def _guide_loop(self) -> None:
        camera = await self.proxy(self._camera, ICamera)
        while self._loop_state is not LoopState.STOPPED:
            try:
                if isinstance(camera, IExposureTime):
                    await camera.set_exposure_time(self._exposure_time)
                filename = await camera.grab_data(broadcast=False, image_type=ImageType.GUIDING)
                await self.process_frame(await Image.from_vfs(self.vfs, filename))
            except NightcrewError as exc:  # a failed exposure: wait a moment, then try again
                log.warning("%s: guide exposure failed: %s", self.name, exc)
                await self.clock.sleep(max(1.0, self._exposure_time))


class ScienceFrameAutoGuiding(BaseGuiding):
    """Guides on the object frames of a science camera (announced with NewImageEvent).

    Args:
        camera: Name of the science camera whose frames are used.
        **kwargs: See :class:`BaseGuiding`.
    """

    def __init__(self, *, camera: str, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._camera_name = camera

    async def open(self) -> None:
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)

    async def on_new_image(self, event: NewImageEvent, sender: str) -> bool:
        if sender != self._camera_name or self._loop_state is LoopState.STOPPED:
            return False
        if event.image_type not in (None, ImageType.OBJECT):
            return False
        await self.process_frame(await Image.from_vfs(self.vfs, event.filename))
        return True


def _target_of(image: Image) -> tuple[str | None, float, float] | None:
    """(OBJECT, RA, Dec) the telescope aimed at, offsets removed; None without RA/DEC cards."""
    header = image.header
    values = [header.get(k) for k in ("RA", "DEC")]
    if not all(isinstance(v, int | float) for v in values):
        return None
    ra_off, dec_off = (header.get(k, 0.0) for k in ("RAOFF", "DECOFF"))
    obj = header.get("OBJECT")
    return (
        obj if isinstance(obj, str) else None,
        float(values[0]) - float(ra_off),
        float(values[1]) - float(dec_off),
    )


def _moved(
    old: tuple[str | None, float, float], new: tuple[str | None, float, float] | None, limit_arcsec: float
) -> bool:
    if new is None:
        return False
    return old[0] != new[0] or angular_separation(old[1], old[2], new[1], new[2]) * 3600.0 > limit_arcsec
