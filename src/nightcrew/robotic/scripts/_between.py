"""What the imaging script does between two science frames: dither, grade the last, refocus.

* **Dither** (the configuration's ``dither_config``): after every ``every`` frames the telescope's
  RA/Dec offsets move to the next position of the pattern (:mod:`._dither`); the script stops a
  running guider before the move and starts it after, so it takes its reference on the new position.
  Offsets the acquisition or the guider set stay: the dither moves them by its own step. A mount
  without offsets is sent to the dithered position instead.
* **Grading** (the script's ``grading``): each frame is read through the VFS and measured
  (:func:`~nightcrew.images.quality.measure_frame_quality`), then graded against the night
  (:class:`~nightcrew.images.grading.FrameGrader`); a failed frame is taken again, at most
  ``max_retakes`` times, and a log line gives the grade and why.
* **Refocus** (the script's ``refocus_triggers``): before a frame, a focus series runs when a
  trigger fires (:func:`~nightcrew.focus.refocus.refocus_cause`): the graded frames' FWHM rose,
  the temperature changed, time passed, or the filter changed. Filter focus offsets
  (``filter_focus_offsets``) move the focuser's offset whenever the filter is set.
"""

from __future__ import annotations

import asyncio
import logging
import statistics
from collections import deque
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from typing import Any

from nightcrew.errors import NightcrewError
from nightcrew.focus.refocus import FocusState, RefocusTriggers, refocus_cause
from nightcrew.focus.sources import TemperatureSource
from nightcrew.images import Image
from nightcrew.images.grading import FrameGrade, FrameGrader, GradingPolicy
from nightcrew.images.quality import measure_frame_quality
from nightcrew.interfaces import (
    IAutoFocus,
    IAutoGuiding,
    IFocuser,
    IOffsetsRaDec,
    IPierSide,
    ITelescope,
)
from nightcrew.robotic.runner import Script
from nightcrew.robotic.scripts._dither import dither_offset, dither_to_radec, dithers_before
from nightcrew.robotic.scripts._flip import RefocusAfterFlip
from nightcrew.robotic.scripts._instrument import FILTER_ELEMENT
from nightcrew.robotic.scripts._steps import step
from nightcrew.robotic.tasks import Configuration, DitherConfig, InstrumentConfig, MovingTarget, Target
from nightcrew.robotic.temperature_source import read_temperature
from nightcrew.vfs import VirtualFileSystem

__all__ = ["Dithering", "Grading", "Pointing", "Refocusing", "focus_series", "setup_of"]

log = logging.getLogger(__name__)

#: Frames whose FWHM is compared with the one after the last focus (their median: one bad frame
#: does not refocus).
RECENT_FRAMES = 3


def setup_of(config: InstrumentConfig) -> tuple[str, int, float]:
    """The setup a frame is graded with: filter, binning, exposure time."""
    return config.optical_elements.get(FILTER_ELEMENT, ""), config.binning, config.exposure_time


@dataclass
class Pointing:
    """What a flip or a dither changes and needs: the mount, its pier side and offsets, the
    target, the guider running, the dither so far."""

    telescope: ITelescope
    pier: IPierSide | None
    target: Target | MovingTarget
    config: Configuration
    guider: IAutoGuiding | None
    offsets: IOffsetsRaDec | None
    dithering: Dithering


@dataclass
class Dithering:
    """The dither of one task run: the positions used so far and the step applied last."""

    config: DitherConfig
    target: Target | None  # None for a moving target: an offset would end the following
    seed: str  # the task: a resumed run dithers to the same random positions
    frames: int = 0  # frames kept since the run began
    position: int = 0  # index of the pattern position the telescope is at
    applied: tuple[float, float] = (0.0, 0.0)  # (dra, ddec) degrees this dither added to the offsets

    def count_frame(self) -> None:
        self.frames += 1

    def forget_offsets(self) -> None:
        """The mount was sent to the target again (a flip): no dither step is in its offsets now."""
        self.applied = (0.0, 0.0)

    @property
    def due(self) -> bool:
        """Whether the next frame is to be taken at another position than the last (never for a
        retake: no frame was kept since)."""
        return self.target is not None and dithers_before(self.config, self.frames) != self.position

    async def move(self, telescope: ITelescope, offsets: IOffsetsRaDec | None) -> None:
        """Move the telescope to the position the next frame is due at (guiding stopped first)."""
        if self.target is None:
            return  # never due for a moving target
        due = dithers_before(self.config, self.frames)
        self.position = due
        east, north = dither_offset(self.config, due, seed=self.seed)
        dra, ddec = dither_to_radec((east, north), self.target.dec)
        log.info('dither %d to %+.1f" east, %+.1f" north of %s', due, east, north, self.target.name)
        if offsets is not None:
            now_ra, now_dec = await step("read the offsets", offsets.get_offsets_radec())
            moved = (now_ra + dra - self.applied[0], now_dec + ddec - self.applied[1])
            await step(f"dither {due}", offsets.set_offsets_radec(*moved))
        else:
            ra, dec = (self.target.ra + dra) % 360.0, self.target.dec + ddec
            await step(f"dither {due}", telescope.move_radec(ra, dec), on_cancel=telescope.stop_motion)
        self.applied = (dra, ddec)


class Grading:
    """Grades science frames against the night (one grader for every task the script runs)."""

    def __init__(self, policy: GradingPolicy) -> None:
        self.policy = policy
        self.grader = FrameGrader(policy)
        self.recent: deque[float] = deque(maxlen=RECENT_FRAMES)  # FWHMs of the last frames

    async def grade(self, vfs: VirtualFileSystem, path: str, setup: object, time: float) -> FrameGrade:
        """The grade of the frame at ``path``; a frame that cannot be read or measured passes
        (grading must not stop the night), with a warning."""
        try:
            image = await Image.from_vfs(vfs, path)
            quality = await asyncio.to_thread(measure_frame_quality, image)
        except (NightcrewError, OSError, ValueError) as exc:  # a frame not measured is kept
            log.warning("could not grade %s, kept ungraded: %s", path, exc)
            return FrameGrade(True, "not measured")
        grade = self.grader.grade(quality, setup, time)
        if quality.stars:
            self.recent.append(quality.fwhm)
        log.info(
            "graded %s: %s (FWHM %.2f, ellipticity %.2f, %d stars, sky %.4g)%s",
            path,
            grade.label,
            quality.fwhm,
            quality.ellipticity,
            quality.stars,
            quality.sky,
            f": {grade.why}" if grade.why else "",
        )
        return grade

    def recent_fwhm(self) -> float | None:
        """The median FWHM of the last :data:`RECENT_FRAMES` frames; None before that many."""
        return statistics.median(self.recent) if len(self.recent) == RECENT_FRAMES else None


async def focus_series(script: Script, series: RefocusAfterFlip, what: str) -> None:
    """Run ``series`` by its IAutoFocus module, as the step ``what``; the focus found is logged."""
    focus = await step("connect to the focus module", script.proxy_as(series.focus, IAutoFocus))
    best, error = await step(
        what, focus.auto_focus(series.count, series.step, series.exposure_time), on_cancel=focus.abort
    )
    log.info("%s: focus %.4f +- %.4f mm", what, best, error)


@dataclass
class Refocusing:
    """Refocus triggers, the focus series they run, and the filter focus offsets."""

    triggers: RefocusTriggers
    series: RefocusAfterFlip
    focuser: str | None = None
    filter_offsets: Mapping[str, float] = field(default_factory=dict)
    temperature: TemperatureSource | None = None  # for the temperature trigger
    last: FocusState | None = None

    @classmethod
    def from_options(
        cls,
        options: Mapping[str, Any],
        focuser: str | None,
        offsets: Mapping[str, Any],
        temperature: TemperatureSource | None = None,
    ) -> Refocusing:
        """From the script's ``refocus_triggers`` (trigger and series keys in one mapping)."""
        trigger_keys = {"fwhm_rise", "interval", "filter_change", "temperature_change"}
        known = trigger_keys | {f.name for f in fields(RefocusAfterFlip)}
        unknown = sorted(set(options) - known)
        if unknown:
            raise ValueError(f"{unknown[0]} is not an option; known: {', '.join(sorted(known))}")
        series = RefocusAfterFlip.from_options({k: v for k, v in options.items() if k not in trigger_keys})
        triggers = RefocusTriggers(**{k: v for k, v in options.items() if k in trigger_keys})
        if triggers.temperature_change is not None and temperature is None:
            raise ValueError("temperature_change needs the script's focus_temperature (module and sensor)")
        filter_offsets = {str(k): float(v) for k, v in offsets.items()}
        return cls(triggers, series, focuser, filter_offsets, temperature)

    async def refocus_if_due(self, script: Script, filter_name: str | None, grading: Grading | None) -> bool:
        """Run the focus series if a trigger fires before a frame in ``filter_name``; whether it ran."""
        now, temperature = script.clock.time(), await self._temperature(script)
        if self.last is None:  # the task starts in focus (the mastermind focused before it)
            self.last = FocusState(time=now, temperature=temperature, filter_name=filter_name)
        recent = grading.recent_fwhm() if grading is not None else None
        if self.last.fwhm is None and recent is not None:
            self.last = replace(self.last, fwhm=recent)
        cause = refocus_cause(
            self.triggers, self.last, time=now, temperature=temperature, filter_name=filter_name, fwhm=recent
        )
        if cause is None:
            return False
        log.info("refocusing: %s", cause)
        await focus_series(script, self.series, "refocus")
        self.last = FocusState(time=script.clock.time(), temperature=temperature, filter_name=filter_name)
        if grading is not None:
            grading.recent.clear()  # the FWHM after this focus is measured anew
        return True

    async def _temperature(self, script: Script) -> float | None:
        """The sensor's temperature (°C) when the temperature trigger is on and it answers."""
        if self.triggers.temperature_change is None or self.temperature is None:
            return None
        try:  # a sensor the module lacks is said, with the ones it has (not a silent None)
            return await read_temperature(script, self.temperature)
        except NightcrewError as exc:
            log.warning("no temperature for the refocus trigger: %s", exc)
            return None

    async def apply_filter_offset(self, script: Script, filter_name: str | None) -> None:
        """Move the focuser's offset to ``filter_name``'s (0 for a filter not listed)."""
        if not self.filter_offsets or self.focuser is None or filter_name is None:
            return
        focuser = await step("connect to the focuser", script.proxy_as(self.focuser, IFocuser))
        offset = self.filter_offsets.get(filter_name, 0.0)
        await step(f"set the focus offset of filter {filter_name}", focuser.set_focus_offset(offset))
