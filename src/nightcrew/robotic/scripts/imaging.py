"""The default imaging script: EXPOSE and REPEAT_EXPOSE configurations on one telescope and camera."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Mapping
from typing import Any

from nightcrew.astro.ephemeris import next_rise
from nightcrew.astro.pier import hour_angle
from nightcrew.errors import ConfigError, MoveError, NotSupportedError
from nightcrew.focus.sources import source_from_config
from nightcrew.images.grading import GradingPolicy
from nightcrew.interfaces import (
    IAcquisition,
    IAutoGuiding,
    ICamera,
    IFilters,
    ImageType,
    INonSidereal,
    IOffsetsRaDec,
    IPierSide,
    ITelescope,
)
from nightcrew.robotic.runner import ProgressCallback, ProgressReporter, Script, the_configuration
from nightcrew.robotic.scheduler.constraints import altitude_for_airmass
from nightcrew.robotic.scripts._between import (
    Dithering,
    Grading,
    Pointing,
    Refocusing,
    focus_series,
    setup_of,
)
from nightcrew.robotic.scripts._flip import RefocusAfterFlip, flip_wait
from nightcrew.robotic.scripts._instrument import (
    FILTER_ELEMENT,
    CutShortCallback,
    Instrument,
    instrument_supported,
)
from nightcrew.robotic.scripts._repeat import RepeatTiming
from nightcrew.robotic.scripts._steps import config_option, quietly, step
from nightcrew.robotic.tasks import (
    AcquisitionMode,
    Configuration,
    ConfigurationType,
    GuidingConfig,
    GuidingMode,
    InstrumentConfig,
    MovingTarget,
    SatelliteTarget,
    Target,
    Task,
    target_radec,
)

__all__ = ["ImagingScript"]

log = logging.getLogger(__name__)

_TYPES = frozenset({ConfigurationType.EXPOSE, ConfigurationType.REPEAT_EXPOSE})


class ImagingScript(Script):
    """Images a target: slew, acquire, guide, expose every instrument config, stop guiding.

    EXPOSE takes each instrument config's ``exposure_count`` frames (filter, binning and exposure
    time set first) as OBJECT frames, reporting progress after each. REPEAT_EXPOSE cycles through the
    instrument configs until ``repeat_duration`` clock seconds have passed (see
    :class:`~nightcrew.robotic.scripts._repeat.RepeatTiming`). Acquisition runs when the
    configuration asks for it and an acquisition module is configured (skipped with a warning
    otherwise). Optional guiding that fails to start only gives a warning; required guiding fails
    the configuration. Aborted or failed, the script aborts the exposure and stops guiding.

    On a German-equatorial mount (one that reports its pier side) a frame that would end more than
    ``flip_past_meridian`` degrees past the meridian with the counterweight up is preceded by a
    meridian flip (see :mod:`nightcrew.robotic.scripts._flip`): wait for the meridian if need be,
    stop guiding, slew to the target again (the mount changes sides), centre it again by plate solve
    (the acquisition module; with ``centre_after_flip`` also for a task that did not ask for
    acquisition), refocus if ``refocus_after_flip`` is set, restart guiding.

    Between frames (see :mod:`nightcrew.robotic.scripts._between`) the script dithers as the
    configuration's ``dither_config`` asks, grades every frame with ``grading`` (a failed frame is
    taken again) and refocuses when one of ``refocus_triggers`` fires.

    A task carrying progress from an interrupted attempt is resumed: only the missing frames of
    each instrument config are taken, a REPEAT_EXPOSE only repeats for the time it has left.

    Args:
        telescope: Module offering ITelescope.
        camera: Module offering ICamera (IExposureTime, IBinning if binning is asked for).
        filters: Module offering IFilters; None: no filter wheel.
        acquisition: Module offering IAcquisition; None: never acquire.
        autoguider: Module offering IAutoGuiding; None: never guide.
        flip_past_meridian: Degrees (0..90) a frame may end past the meridian with the
            counterweight up before the script flips first; keep it below the mount's own limit.
        centre_after_flip: After a flip, centre the target by the acquisition module even when the
            task did not ask for acquisition (the mount's pointing differs from side to side);
            False: only when it asked.
        refocus_after_flip: Run a focus series after each flip: a mapping of ``focus`` (IAutoFocus
            module), ``count``, ``step`` (mm) and ``exposure_time`` (s); None: no refocus.
        grading: Grade every science frame against the night and take failed ones again: a
            mapping of :class:`~nightcrew.images.grading.GradingPolicy` fields (``{}``: the
            defaults); None: no grading.
        refocus_triggers: Refocus between frames: ``fwhm_rise`` (fraction), ``temperature_change``
            (°C), ``interval`` (s), ``filter_change`` (bool), and the series as in
            ``refocus_after_flip``; None: never.
        focuser: Module offering IFocuser, for ``filter_focus_offsets``.
        filter_focus_offsets: Filter name to focuser offset (mm), set with the filter.
        focus_temperature: Where ``temperature_change`` reads the temperature, as the
            mastermind's key of that name: ``{module, sensor}`` (ITemperatures) or
            ``{module, weather_sensor}`` (IWeather).
    """

    def __init__(
        self,
        *,
        telescope: str | ITelescope = "telescope",
        camera: str | ICamera = "camera",
        filters: str | IFilters | None = "filters",
        acquisition: str | IAcquisition | None = None,
        autoguider: str | IAutoGuiding | None = None,
        flip_past_meridian: float = 0.0,
        centre_after_flip: bool = True,
        refocus_after_flip: Mapping[str, Any] | None = None,
        grading: Mapping[str, Any] | None = None,
        refocus_triggers: Mapping[str, Any] | None = None,
        focuser: str | None = None,
        filter_focus_offsets: Mapping[str, float] | None = None,
        focus_temperature: Mapping[str, Any] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not 0.0 <= flip_past_meridian < 90.0:
            raise ConfigError(
                f"must be within 0..90 degrees, got {flip_past_meridian}", key="flip_past_meridian"
            )
        self._flip_past_meridian = float(flip_past_meridian)
        self._centre_after_flip = bool(centre_after_flip)
        self._refocus = config_option(
            "refocus_after_flip",
            lambda: None if refocus_after_flip is None else RefocusAfterFlip.from_options(refocus_after_flip),
        )
        self._grading = config_option(
            "grading", lambda: None if grading is None else Grading(GradingPolicy.from_options(grading))
        )
        if filter_focus_offsets and focuser is None:
            raise ConfigError("filter focus offsets need the focuser to move", key="focuser")
        if refocus_triggers and refocus_triggers.get("fwhm_rise") is not None and grading is None:
            raise ConfigError(
                "a FWHM rise is measured on graded frames: set grading", key="refocus_triggers.fwhm_rise"
            )
        temperature = (
            None if focus_temperature is None else source_from_config(focus_temperature, "focus_temperature")
        )
        self._refocusing = config_option(
            "refocus_triggers",
            lambda: (
                None
                if refocus_triggers is None and not filter_focus_offsets
                else Refocusing.from_options(
                    refocus_triggers or {},
                    focuser,
                    filter_focus_offsets or {},
                    temperature,
                )
            ),
        )
        self._telescope, self._camera, self._filters = telescope, camera, filters
        self._acquisition, self._autoguider = acquisition, autoguider

    @property
    def flip_past_meridian(self) -> float:
        """Degrees a frame may end past the meridian with the counterweight up before a flip."""
        return self._flip_past_meridian

    async def can_run(self, task: Task) -> bool:
        config = the_configuration(task)
        if config.type not in _TYPES or config.target is None:
            return False
        guiding = config.guiding_config
        guiding_required = guiding.mode is GuidingMode.ON and not guiding.optional
        if guiding_required and not await self.offers(self._autoguider, IAutoGuiding):
            return False
        return await self.offers(self._telescope, ITelescope) and await instrument_supported(
            self, self._camera, self._filters, config
        )

    async def run(self, task: Task, progress: ProgressCallback) -> None:
        config = the_configuration(task)
        if config.type not in _TYPES or config.target is None:
            raise NotSupportedError(
                f"{type(self).__name__} runs EXPOSE and REPEAT_EXPOSE with a target, not {config.type}"
            )
        target = config.target
        telescope = await step("connect to the telescope", self.proxy(self._telescope, ITelescope))
        instrument = await step(
            "connect to the camera", Instrument.connect(self, self._camera, self._filters)
        )
        if isinstance(target, SatelliteTarget):
            await step(f"wait for {target.name}'s pass", self._wait_for_pass(target, config))
        await step(
            f"slew to {target.name}", self._point_at(telescope, target), on_cancel=telescope.stop_motion
        )
        await self._acquire(config)
        pier = await self.optional_proxy(self._telescope, IPierSide)
        pointing = Pointing(
            telescope,
            pier,
            target,
            config,
            await self._start_guiding(config.guiding_config),
            await self.optional_proxy(self._telescope, IOffsetsRaDec),
            Dithering(config.dither_config, target if isinstance(target, Target) else None, seed=task.id),
        )
        try:
            reporter = ProgressReporter(task, progress)
            if config.type is ConfigurationType.REPEAT_EXPOSE:
                await self._expose_repeatedly(config, instrument, reporter, pointing)
            else:
                await self._expose(config, instrument, reporter, pointing)
        finally:
            if pointing.guider is not None:
                await quietly("stop guiding", pointing.guider.stop)

    async def _flip_if_needed(self, pointing: Pointing, seconds: float) -> bool:
        """Flip before a frame of ``seconds`` that would carry the mount too far past the meridian;
        whether it did."""
        site = self.site
        if pointing.pier is None or site is None:
            return False
        side = await pointing.pier.get_pier_side()
        target = pointing.target
        ha = hour_angle(*target_radec(target, site, self.clock.time()), site.longitude, self.clock.time())
        wait = flip_wait(ha, seconds, side, self._flip_past_meridian)
        if wait is None:
            return False
        if wait > 0:
            log.info("%s reaches the meridian in %.0f s: waiting for it to flip", target.name, wait)
            await self.clock.sleep(wait)
        log.info("meridian flip for %s from the %s side of the pier", target.name, side)
        if pointing.guider is not None:
            await quietly("stop guiding", pointing.guider.stop)
            pointing.guider = None
        telescope = pointing.telescope
        await step(
            f"meridian flip to {target.name}",
            self._point_at(telescope, target),
            on_cancel=telescope.stop_motion,
        )
        if await pointing.pier.get_pier_side() is side:
            log.warning("the mount stayed on the %s side of the pier after the flip", side)
        pointing.dithering.forget_offsets()
        await self._acquire(pointing.config, after_flip=True)
        await self._refocus_after_flip()
        pointing.guider = await self._start_guiding(pointing.config.guiding_config)
        return True

    async def _dither_if_due(self, pointing: Pointing) -> None:
        """Dither before the next frame if it is due at another position; guiding paused for it."""
        if not pointing.dithering.due:
            return
        if pointing.guider is not None:
            await quietly("stop guiding for the dither", pointing.guider.stop)
        await pointing.dithering.move(pointing.telescope, pointing.offsets)
        if pointing.guider is not None:
            pointing.guider = await self._start_guiding(pointing.config.guiding_config)

    async def _wait_for_pass(self, target: SatelliteTarget, config: Configuration) -> None:
        """Wait until the satellite has climbed above the configuration's airmass limit (the
        scheduler plans a satellite into the slice in which its pass rises)."""
        site = self.site
        if site is None:
            raise ConfigError("a satellite's pass needs the observatory's site", key="site")
        lowest = altitude_for_airmass(config.constraints.max_airmass)
        now = self.clock.time()
        rises = next_rise(target.body(), site, now, lowest)
        if rises is None:
            raise MoveError(f"{target.name} does not rise above {lowest:.1f}° within 15 minutes")
        if rises > now:
            log.info("waiting %.0f s for %s to rise above %.1f°", rises - now, target.name, lowest)
            await self.clock.sleep(rises - now)

    async def _point_at(self, telescope: ITelescope, target: Target | MovingTarget) -> None:
        """Slew to ``target``; a moving one is followed along its ephemeris where the mount can
        (INonSidereal), else pointed at where it is now."""
        if not isinstance(target, Target):
            follower = await self.optional_proxy(self._telescope, INonSidereal)
            if follower is not None:
                await follower.move_ephemeris(target.model_dump(mode="json"))
                return
            log.warning(
                "%s cannot follow a moving target: pointing at %s where it is now",
                self._telescope,
                target.name,
            )
        await telescope.move_radec(*target_radec(target, self.site, self.clock.time()))

    async def _refocus_after_flip(self) -> None:
        if self._refocus is not None:
            await focus_series(self, self._refocus, "refocus after the flip")

    async def _acquire(self, config: Configuration, *, after_flip: bool = False) -> None:
        asked = config.acquisition_config.mode is not AcquisitionMode.OFF
        if not asked and not (after_flip and self._centre_after_flip and self._acquisition is not None):
            return
        if self._acquisition is None:
            log.warning(
                "acquisition %s asked for, but no acquisition module configured",
                config.acquisition_config.mode,
            )
            return
        try:
            acquisition = await step(
                "connect to the acquisition", self.proxy(self._acquisition, IAcquisition)
            )
            result = await step("acquisition", acquisition.acquire_target(), on_cancel=acquisition.abort)
        except Exception as exc:  # centring the task did not ask for must not end it
            if asked:
                raise
            log.warning("centring after the flip failed, exposing without it: %s", exc)
            return
        log.info("acquired: %s", result)

    async def _start_guiding(self, guiding: GuidingConfig) -> IAutoGuiding | None:
        """The started guider; None when not asked for, or when optional and it failed to start."""
        if guiding.mode is GuidingMode.OFF:
            return None
        try:
            if self._autoguider is None:
                raise NotSupportedError("guiding asked for, but no autoguider is configured")
            return await step("start guiding", self._started_guider(self._autoguider, guiding))
        except Exception as exc:  # optional guiding must never stop the exposures
            if not guiding.optional:
                raise
            log.warning("optional guiding did not start, exposing without it: %s", exc)
            return None

    async def _started_guider(self, autoguider: str | IAutoGuiding, guiding: GuidingConfig) -> IAutoGuiding:
        guider = await self.proxy(autoguider, IAutoGuiding)
        if guiding.exposure_time is not None:
            await guider.set_exposure_time(guiding.exposure_time)
        try:
            await guider.start()
        except asyncio.CancelledError:
            await quietly("stop guiding", guider.stop)
            raise
        return guider

    async def _expose(
        self, config: Configuration, instrument: Instrument, reporter: ProgressReporter, pointing: Pointing
    ) -> None:
        for index, instrument_config in enumerate(config.instrument_configs):
            missing = reporter.remaining(index)
            if missing == 0:
                continue  # taken in an earlier attempt
            await self._set_up(instrument, instrument_config)
            for _ in range(missing):
                await self._science_frame(pointing, instrument, reporter, index, instrument_config)

    async def _expose_repeatedly(
        self, config: Configuration, instrument: Instrument, reporter: ProgressReporter, pointing: Pointing
    ) -> None:
        assert config.repeat_duration is not None  # the task model requires it for REPEAT_EXPOSE
        # Resumed after an interruption: only the time left, and a first cycle already taken is
        # not forced again.
        recorded = reporter.progress
        timing = RepeatTiming(self.clock.time(), recorded.repeat_time_left(reporter.request, 0))
        cycles = 1 if recorded.configuration_complete(reporter.request, 0) else 0
        while True:
            for index, instrument_config in enumerate(config.instrument_configs):
                exposure_time = instrument_config.exposure_time
                for number in range(instrument_config.exposure_count):
                    started = self.clock.time()
                    if cycles > 0 and not timing.fits(started, exposure_time):
                        log.info("repeat duration %g s used up after %d cycles", timing.duration, cycles)
                        return
                    if number == 0:
                        await self._set_up(instrument, instrument_config)
                    retakes = await self._science_frame(
                        pointing, instrument, reporter, index, instrument_config
                    )
                    timing.record(started, self.clock.time(), (1 + retakes) * exposure_time)
            cycles += 1

    async def _set_up(self, instrument: Instrument, instrument_config: InstrumentConfig) -> None:
        await instrument.set_up(instrument_config)
        if self._refocusing is not None:
            await self._refocusing.apply_filter_offset(
                self, instrument_config.optical_elements.get(FILTER_ELEMENT)
            )

    async def _science_frame(
        self,
        pointing: Pointing,
        instrument: Instrument,
        reporter: ProgressReporter,
        index: int,
        instrument_config: InstrumentConfig,
    ) -> int:
        """One science frame that counts, taken again while its grade fails (at most
        ``max_retakes`` times); returns how often it was taken again."""
        retakes = 0
        while True:
            flipped = await self._flip_if_needed(pointing, instrument_config.exposure_time)
            await self._dither_if_due(pointing)
            refocused = self._refocusing is not None and await self._refocusing.refocus_if_due(
                self, instrument_config.optical_elements.get(FILTER_ELEMENT), self._grading
            )
            if flipped or refocused:  # the acquisition's and focus frames set their own exposure
                await self._set_up(instrument, instrument_config)
            path = await instrument.expose(
                ImageType.OBJECT, cut_short=_recorder(reporter, index, instrument_config)
            )
            if self._grading is None:
                break
            grade = await self._grading.grade(self.vfs, path, setup_of(instrument_config), self.clock.time())
            if grade.passed:
                break
            if retakes >= self._grading.policy.max_retakes:
                log.warning("kept %s after %d retakes, though it failed: %s", path, retakes, grade.why)
                break
            retakes += 1
            log.info(
                "taking %s again (retake %d of at most %d)", path, retakes, self._grading.policy.max_retakes
            )
        pointing.dithering.count_frame()
        await reporter.add(index)
        return retakes


def _recorder(
    reporter: ProgressReporter, index: int, instrument_config: InstrumentConfig
) -> CutShortCallback:
    """Records a frame of instrument config ``index`` cut short after a fraction of its exposure time."""

    async def record(fraction: float) -> None:
        await reporter.add_cut_short(index, fraction * instrument_config.exposure_time)

    return record
