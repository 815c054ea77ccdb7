"""PANEL_FLAT configurations: flat fields on a flat panel (a flip-flat or a panel behind a closed cover).

The script closes the cover, switches the light on at ``brightness``, measures the bias once (a
zero-second frame) and, per instrument config (filter, binning), finds the exposure time that
brings the frame's median to the target level: test frames (not announced, not counted, removed
once measured) scaled
linearly towards it, :data:`MAX_TEST_FRAMES` at most, between ``min_exposure`` and
``max_exposure``. Then it takes the config's ``exposure_count`` flats (image type ``domeflat``).
Whatever happens - done, failed, cancelled - the light goes off and the cover opens again.

The level is ``extra_params.level`` of the configuration, else the script's ``level`` (ADU,
bias included, below saturation); the instrument config's ``exposure_time`` is the first guess.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

import numpy as np

from nightcrew.errors import ConfigError, NightcrewError, NotSupportedError
from nightcrew.flatfield.fit import FlatSample, target_exposure_time
from nightcrew.images import Image
from nightcrew.interfaces import ICamera, ICoverCalibrator, IFilters, ImageType
from nightcrew.robotic.runner import (
    ProgressCallback,
    ProgressReporter,
    Script,
    ScriptError,
    the_configuration,
)
from nightcrew.robotic.scripts._instrument import Instrument, instrument_supported
from nightcrew.robotic.scripts._steps import quietly, step
from nightcrew.robotic.tasks import ConfigurationType, InstrumentConfig, Task
from nightcrew.robotic.tasks._configuration import SATURATION_ADU

__all__ = ["MAX_TEST_FRAMES", "PanelFlatScript"]

log = logging.getLogger(__name__)

#: Test frames per instrument config before the level counts as out of reach.
MAX_TEST_FRAMES = 5


class PanelFlatScript(Script):
    """Takes flats on a flat panel; see the module docstring.

    Args:
        camera: Module offering ICamera (with IExposureTime).
        filters: Module offering IFilters; None: no filter wheel.
        calibrator: Module offering ICoverCalibrator (cover and light).
        brightness: The light's brightness; None: its maximum.
        level: Target median of a flat, ADU (bias included), below saturation.
        tolerance: Accepted deviation from the level, as a fraction of (level - bias).
        min_exposure, max_exposure: Seconds an exposure may take (short ones show the shutter).
    """

    def __init__(
        self,
        *,
        camera: str | ICamera = "camera",
        filters: str | IFilters | None = "filters",
        calibrator: str | ICoverCalibrator = "calibrator",
        brightness: int | None = None,
        level: float = 30000.0,
        tolerance: float = 0.1,
        min_exposure: float = 0.5,
        max_exposure: float = 60.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not 0 < level < SATURATION_ADU:
            raise ConfigError(f"{level:g} ADU is not below saturation ({SATURATION_ADU} ADU)", key="level")
        if not 0 < tolerance < 1:
            raise ConfigError(f"must be within (0, 1), got {tolerance}", key="tolerance")
        if not 0 < min_exposure < max_exposure:
            raise ConfigError(
                f"need 0 < min_exposure < max_exposure, got {min_exposure} and {max_exposure}",
                key="min_exposure",
            )
        if brightness is not None and not brightness >= 0:
            raise ConfigError(f"must be >= 0 or null, got {brightness}", key="brightness")
        self._camera, self._filters, self._calibrator = camera, filters, calibrator
        self._brightness, self._level, self._tolerance = brightness, float(level), float(tolerance)
        self._exposure_range = (float(min_exposure), float(max_exposure))

    async def can_run(self, task: Task) -> bool:
        config = the_configuration(task)
        if config.type is not ConfigurationType.PANEL_FLAT:
            return False
        if not await self.offers(self._calibrator, ICoverCalibrator):
            return False
        return await instrument_supported(self, self._camera, self._filters, config)

    async def run(self, task: Task, progress: ProgressCallback) -> None:
        config = the_configuration(task)
        if config.type is not ConfigurationType.PANEL_FLAT:
            raise NotSupportedError(f"{type(self).__name__} runs PANEL_FLAT, not {config.type}")
        level = float(config.extra_params.get("level", self._level))
        reporter = ProgressReporter(task, progress)
        if all(reporter.remaining(i) == 0 for i in range(len(config.instrument_configs))):
            return
        instrument = await Instrument.connect(self, self._camera, self._filters)
        panel = await self.proxy(self._calibrator, ICoverCalibrator)
        try:
            await step("close the cover", panel.close_cover())
            brightness = self._brightness
            if brightness is None:
                brightness = await step("read the maximum brightness", panel.get_max_brightness())
            await step(f"switch the light on at {brightness}", panel.calibrator_on(brightness))
            bias = await self._median(
                await step("bias frame", instrument.camera.grab_data(False, ImageType.BIAS))
            )
            for index, instrument_config in enumerate(config.instrument_configs):
                missing = reporter.remaining(index)
                if missing == 0:
                    continue
                await self._find_exposure(instrument, instrument_config, level, bias)
                for _ in range(missing):
                    await instrument.expose(ImageType.DOMEFLAT)
                    await reporter.add(index)
        finally:
            # Shielded: a cancelled task still leaves the light off and the telescope open.
            await asyncio.shield(self._restore(panel))

    async def _find_exposure(
        self, instrument: Instrument, config: InstrumentConfig, level: float, bias: float
    ) -> float:
        """Set up ``config`` and the exposure time that gives ``level``; returns the seconds."""
        if not level > bias:
            raise ScriptError(f"the flat level {level:g} ADU is not above the bias ({bias:.0f} ADU)")
        await instrument.set_up(config)
        assert instrument.exposure_time is not None  # set_up refuses a camera without one
        low, high = self._exposure_range
        seconds = min(max(config.exposure_time, low), high)
        for _ in range(MAX_TEST_FRAMES):
            await step(
                f"set exposure time {seconds:g} s", instrument.exposure_time.set_exposure_time(seconds)
            )
            measured = await self._median(
                await step("test flat", instrument.camera.grab_data(False, ImageType.DOMEFLAT))
            )
            log.info(
                "panel flat: %.3g s gave %.0f ADU (target %.0f, bias %.0f)", seconds, measured, level, bias
            )
            if abs(measured - level) <= self._tolerance * (level - bias):
                return seconds
            wanted = (
                high
                if measured <= bias
                else target_exposure_time(FlatSample(0.0, seconds, measured), level, bias)
            )
            clamped = min(max(wanted, low), high)
            if clamped == seconds:  # at a limit already: the level is out of reach
                side = "faint" if wanted > high else "bright"
                raise ScriptError(
                    f"the panel is too {side} for {level:g} ADU: {measured:.0f} ADU in {seconds:g} s "
                    f"(exposures {low:g}..{high:g} s; change the brightness or the level)"
                )
            seconds = clamped
        raise ScriptError(f"no exposure time reached {level:g} ADU within {MAX_TEST_FRAMES} test frames")

    async def _median(self, filename: str) -> float:
        """The frame's median (ADU); the frame is removed then: a test frame at the wrong level
        must not go into a master flat (``nightcrew reduce`` takes every domeflat it finds)."""
        image = await Image.from_vfs(self.vfs, filename)
        try:
            await self.vfs.remove(filename)
        except NightcrewError as exc:
            log.warning("panel flat: could not remove the test frame %s: %s", filename, exc)
        return float(await asyncio.to_thread(np.median, image.data))

    @staticmethod
    async def _restore(panel: ICoverCalibrator) -> None:
        await quietly("switch the light off", panel.calibrator_off)
        await quietly("open the cover", panel.open_cover)
