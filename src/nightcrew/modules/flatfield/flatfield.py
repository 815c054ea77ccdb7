"""Twilight flat fields: exposure times from the solar altitude, scaled by what the sky really gives.

:meth:`FlatField.flat_field` runs one series in one filter and binning (see
:mod:`nightcrew.flatfield.control` for the T_min/T_max logic at dusk and dawn):

1. set filter, binning and image type; find out whether it is dusk or dawn from the Sun's motion;
2. loop: predict the exposure time from the function at the current solar altitude, divided by the
   measured sky factor; wait while the sky is too bright (dusk) or too dark (dawn), stop when it has
   become too dark (dusk) or too bright (dawn) or enough flats are taken;
3. before each exposure ask the pointing module (if any) to point opposite the Sun with the next
   dither; expose, read the frame's median through the VFS and learn the sky factor from it. The
   first frame is the test exposure; frames within the tolerance of the target count as flats.

While a series runs, the module gives every camera exposure a ``SUNALT`` card (solar altitude at
the exposure's start) and the target and bias levels (``FLATTGT``, ``FLATBIAS``) as an
IFitsHeaderBefore provider, so ``nightcrew flats fit`` can refit the functions from the files alone.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

import numpy as np

from nightcrew.astro import sun_altaz
from nightcrew.errors import AbortedError, ConfigError, DeviceBusyError, InvalidArgumentError, NightcrewError
from nightcrew.flatfield import (
    Decision,
    ExposureTimeFunctions,
    FlatExposureControl,
    FlatLimits,
    twilight_from_altitudes,
)
from nightcrew.interfaces import (
    Binning,
    FitsCard,
    IBinning,
    ICamera,
    IExposureTime,
    IFilters,
    IFitsHeaderBefore,
    IFlatField,
    IImageType,
    ImageType,
    IRunnable,
)
from nightcrew.modules.module import Module
from nightcrew.site import Site

__all__ = ["FlatField"]

log = logging.getLogger(__name__)


class FlatField(Module, IFlatField, IFitsHeaderBefore):
    """Takes twilight flats with exposure times that follow the Sun.

    Args:
        camera: Module offering ICamera, IExposureTime, IBinning and IImageType.
        functions: Filter → binning → exposure time in s as a function of the solar altitude ``h``,
            e.g. ``{V: {"2x2": "exp(-0.92*(h + 6.0))"}}`` (filter ``none`` without a filter wheel).
        filters: Module offering IFilters; None for a camera without a filter wheel.
        pointing: Module offering IRunnable that points the telescope (e.g. FlatFieldPointing),
            run before every exposure; None to leave the telescope alone.
        target: Mean level in ADU a flat should reach.
        bias: Level in ADU of a zero-second frame (subtracted before comparing levels).
        tolerance: Frames within ±tolerance of the target (as a fraction of target - bias) count.
        saturation: Level in ADU above which a frame is taken as saturated.
        min_exposure: T_min in seconds.
        max_exposure: T_max in seconds.
        wait_step: Clock seconds between two looks at the sky while waiting for it to fit.
        max_wait: Clock seconds to wait for the sky at most before giving up.
        **kwargs: Module options; ``site`` is required (the Sun's position needs it).
    """

    def __init__(
        self,
        *,
        camera: str | ICamera,
        functions: dict[str, dict[str, str]],
        filters: str | IFilters | None = None,
        pointing: str | IRunnable | None = None,
        target: float = 30000.0,
        bias: float = 0.0,
        tolerance: float = 0.2,
        saturation: float = 60000.0,
        min_exposure: float = 1.0,
        max_exposure: float = 30.0,
        wait_step: float = 10.0,
        max_wait: float = 3600.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if self.site is None:
            raise ConfigError("flat fields need the observatory site for the Sun's position", key="site")
        self._functions = ExposureTimeFunctions(functions, "functions")
        try:
            self._limits = FlatLimits(target, bias, tolerance, saturation, min_exposure, max_exposure)
        except ValueError as exc:
            raise ConfigError(str(exc), key="target") from None
        if not (wait_step > 0 and max_wait >= 0):
            raise ConfigError(
                f"need wait_step > 0 and max_wait >= 0, got {wait_step}, {max_wait}", key="wait_step"
            )
        self._camera, self._filters, self._pointing = camera, filters, pointing
        self._wait_step, self._max_wait = float(wait_step), float(max_wait)
        self._task: asyncio.Task[tuple[int, float]] | None = None
        self._aborting = False

    @property
    def _observatory(self) -> Site:
        assert self.site is not None  # checked in the constructor
        return self.site

    # --- IFlatField / IAbortable ---------------------------------------------------------------

    async def flat_field(
        self, count: int, binning: Binning | None = None, filter_name: str | None = None
    ) -> tuple[int, float]:
        if self._task is not None:
            raise DeviceBusyError(f"{self.name} is already taking flats; wait or abort()")
        if count < 1:
            raise InvalidArgumentError(f"count must be >= 1, got {count}")
        self._aborting = False
        self._task = asyncio.create_task(self._series(count, binning, filter_name))
        try:
            return await self._task
        except asyncio.CancelledError:
            current = asyncio.current_task()
            if self._aborting and not (current and current.cancelling()):
                raise AbortedError("flat fields aborted") from None
            raise
        finally:
            self._task = None

    async def abort(self) -> None:
        task = self._task
        if task is not None and not task.done():
            log.info("%s: aborting flat fields", self.name)
            self._aborting = True
            task.cancel()
            await asyncio.wait([task])

    # --- IFitsHeaderBefore ---------------------------------------------------------------------

    async def get_fits_header_before(self, namespaces: list[str] | None = None) -> dict[str, FitsCard]:
        if self._task is None:
            return {}
        altitude, _ = sun_altaz(self._observatory, self.clock.time())
        return {
            "SUNALT": (round(altitude, 4), "Sun altitude at exposure start [deg]"),
            "FLATTGT": (self._limits.target, "Flat fields: target level [ADU]"),
            "FLATBIAS": (self._limits.bias, "Flat fields: bias level assumed [ADU]"),
        }

    # --- the series ----------------------------------------------------------------------------

    async def _series(
        self, count: int, binning: Binning | None, filter_name: str | None
    ) -> tuple[int, float]:
        target: Any = self._camera  # a name, or a local camera offering all four interfaces
        camera = await self.proxy(target, ICamera)
        exposure = await self.proxy(target, IExposureTime)
        binner = await self.proxy(target, IBinning)
        if binning is not None:
            await binner.set_binning(binning.x, binning.y)
        current = await binner.get_binning()
        filter_name = await self._set_filter(filter_name)
        try:
            function = self._functions.function(filter_name, (current.x, current.y))
        except ValueError as exc:
            raise InvalidArgumentError(str(exc)) from None
        await (await self.proxy(target, IImageType)).set_image_type(ImageType.SKYFLAT)

        now = self.clock.time()
        twilight = twilight_from_altitudes(
            sun_altaz(self._observatory, now)[0], sun_altaz(self._observatory, now + 60.0)[0]
        )
        control = FlatExposureControl(self._limits, twilight)
        log.info("%s: %d %s flats in %s, binning %s", self.name, count, twilight, filter_name, current)
        flats, total, frames, waited = 0, 0.0, 0, 0.0
        while flats < count and frames < 3 * count + 5:  # a bound in case the sky never settles
            altitude, _ = sun_altaz(self._observatory, self.clock.time())
            modelled = self._functions.evaluate(function, altitude)
            seconds = control.exposure_time(modelled)
            decision = control.decide(seconds)
            if decision is Decision.STOP:
                log.info("%s: %.1f s needed at h=%.2f°: %s is over", self.name, seconds, altitude, twilight)
                break
            if decision is Decision.WAIT:
                if waited >= self._max_wait:
                    log.warning("%s: waited %.0f s for the sky, giving up", self.name, waited)
                    break
                await self.clock.sleep(self._wait_step)
                waited += self._wait_step
                continue
            if self._pointing is not None:
                await (await self.proxy(self._pointing, IRunnable)).run()
                altitude, _ = sun_altaz(self._observatory, self.clock.time())
                modelled = self._functions.evaluate(function, altitude)
                seconds = control.clip(control.exposure_time(modelled))
            level = await self._expose(camera, exposure, seconds)
            frames += 1
            good = control.learn(seconds, modelled, level)
            log.info(
                "%s: %s %.2f s at h=%.2f° gave %.0f ADU (sky factor %.3f)%s",
                self.name, "flat" if good else "test", seconds, altitude, level, control.sky_factor,
                "" if good else ", not counted",
            )  # fmt: skip
            if good:
                flats += 1
                total += seconds
        return flats, total

    async def _set_filter(self, filter_name: str | None) -> str | None:
        if self._filters is None:
            if filter_name is not None:
                raise InvalidArgumentError(f"{self.name} has no filter wheel to set {filter_name}")
            return None
        wheel = await self.proxy(self._filters, IFilters)
        if filter_name is not None:
            await wheel.set_filter(filter_name)
            return filter_name
        return await wheel.get_filter()

    async def _expose(self, camera: ICamera, exposure: IExposureTime, seconds: float) -> float:
        await exposure.set_exposure_time(seconds)
        try:
            filename = await camera.grab_data()
        except asyncio.CancelledError:
            try:
                await camera.abort()
            except NightcrewError as exc:
                log.warning("%s: camera abort failed: %s", self.name, exc)
            raise
        return await self._level(filename)

    async def _level(self, filename: str) -> float:
        """Median of the frame: robust against stars and cosmic rays."""
        hdus = await self.vfs.read_fits(filename)
        data = hdus[0].data
        if data is None:
            raise InvalidArgumentError(f"{filename} has no image data")
        return float(await asyncio.to_thread(np.median, data))
