"""The camera side of a script: set up an instrument configuration, take (and abort) exposures.

A science exposure interrupted by the script's cancellation (the mastermind aborts the task for
bad weather, a closing roof or dawn) is stopped rather than aborted when the camera can
(IStoppableExposure): the light it collected is read out and kept, its header says it was cut
short, and the script hears how much of its exposure time it got (the camera's own progress just
before the stop), for the task's progress. Other frames, and cameras that can only abort (INDI),
are aborted and nothing is kept.

A cooled camera still on its way to the set point (the cooling schedule started after dusk, or
a warm camera restarted) is waited for before the first frame of a configuration - at most
``COOLER_SETTLE_TIMEOUT`` clock seconds, then the frames are taken (and flagged off the set point).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from dataclasses import dataclass

from nightcrew.clock import Clock
from nightcrew.errors import NotSupportedError
from nightcrew.images.calibration import TEMPERATURE_MARGIN
from nightcrew.interfaces import (
    ExposureStatus,
    IBinning,
    ICamera,
    ICooling,
    IExposureTime,
    IFilters,
    ImageType,
    IStoppableExposure,
)
from nightcrew.robotic.cooling import cooler_settled
from nightcrew.robotic.runner import Script
from nightcrew.robotic.scripts._steps import quietly, step
from nightcrew.robotic.tasks import Configuration, InstrumentConfig

__all__ = ["FILTER_ELEMENT", "CutShortCallback", "Instrument", "instrument_supported"]

log = logging.getLogger(__name__)

#: The optical element the scripts know how to set: ``optical_elements: {filter: V}``.
FILTER_ELEMENT = "filter"

#: Called with the fraction (0-1) of its exposure time a frame got before it was stopped and kept.
CutShortCallback = Callable[[float], Awaitable[None]]

#: Clock seconds a configuration waits for the cooler to reach its set point; clock seconds between looks.
COOLER_SETTLE_TIMEOUT, COOLER_SETTLE_POLL = 900.0, 10.0


async def instrument_supported(
    script: Script,
    camera: str | ICamera,
    filters: str | IFilters | None,
    configuration: Configuration,
    *,
    timed: bool = True,
    use_filters: bool = True,
) -> bool:
    """Whether the camera (and filter wheel) can take every instrument config of ``configuration``.

    Args:
        timed: The exposures need a settable exposure time (not for biases).
        use_filters: Filters named in the instrument configs must be in the filter wheel.
    """
    if not await script.offers(camera, ICamera):
        return False
    configs = configuration.instrument_configs
    if timed and not await script.offers(camera, IExposureTime):
        return False
    if any(c.binning != 1 for c in configs) and not await script.offers(camera, IBinning):
        return False
    unknown = {key for c in configs for key in c.optical_elements if key != FILTER_ELEMENT}
    if unknown:
        log.info("optical elements %s are not supported", ", ".join(sorted(unknown)))
        return False
    wanted = {c.optical_elements[FILTER_ELEMENT] for c in configs if FILTER_ELEMENT in c.optical_elements}
    if not use_filters or not wanted:
        return True
    wheel = await script.optional_proxy(filters, IFilters)
    available = set(await wheel.list_filters()) if wheel is not None else set()
    return wanted <= available


@dataclass(frozen=True)
class Instrument:
    """Proxies for one camera and its optional filter wheel, with what the camera offers."""

    camera: ICamera
    exposure_time: IExposureTime | None
    binning: IBinning | None
    filters: IFilters | None
    stoppable: IStoppableExposure | None = None
    cooling: ICooling | None = None
    clock: Clock | None = None

    @classmethod
    async def connect(
        cls, script: Script, camera: str | ICamera, filters: str | IFilters | None
    ) -> Instrument:
        """Proxies for ``camera`` (IExposureTime and IBinning if offered) and ``filters`` if there."""
        return cls(
            camera=await script.proxy(camera, ICamera),
            exposure_time=await script.optional_proxy(camera, IExposureTime),
            binning=await script.optional_proxy(camera, IBinning),
            filters=await script.optional_proxy(filters, IFilters),
            stoppable=await script.optional_proxy(camera, IStoppableExposure),
            cooling=await script.optional_proxy(camera, ICooling),
            clock=script.clock,
        )

    async def set_up(self, config: InstrumentConfig, *, timed: bool = True, use_filter: bool = True) -> None:
        """Filter, binning and exposure time of ``config``.

        Raises:
            NotSupportedError: The camera or filter wheel cannot do what ``config`` asks.
            ScriptError: A device failed.
        """
        filter_name = config.optical_elements.get(FILTER_ELEMENT)
        if use_filter and filter_name is not None:
            if self.filters is None:
                raise NotSupportedError(f"filter {filter_name} requested, but no filter wheel is available")
            await step(f"set filter {filter_name}", self.filters.set_filter(filter_name))
        if self.binning is not None:
            await step(
                f"set binning {config.binning}", self.binning.set_binning(config.binning, config.binning)
            )
        elif config.binning != 1:
            raise NotSupportedError(f"binning {config.binning} requested, but the camera cannot bin")
        if timed:
            if self.exposure_time is None:
                raise NotSupportedError("the camera has no settable exposure time")
            await step(
                f"set exposure time {config.exposure_time:g} s",
                self.exposure_time.set_exposure_time(config.exposure_time),
            )
        await self._wait_for_cooler()

    async def _wait_for_cooler(self) -> None:
        """Until the cooler is at its set point, or :data:`COOLER_SETTLE_TIMEOUT` has passed."""
        if self.cooling is None or self.clock is None:
            return
        deadline = self.clock.time() + COOLER_SETTLE_TIMEOUT
        while not cooler_settled(
            status := await step("read the cooling", self.cooling.get_cooling()), TEMPERATURE_MARGIN
        ):
            if self.clock.time() >= deadline:
                log.warning(
                    "the detector is at %.1f °C after %g s, not at its set point %g °C: exposing anyway",
                    status.temperature,
                    COOLER_SETTLE_TIMEOUT,
                    status.setpoint,
                )
                return
            await self.clock.sleep(COOLER_SETTLE_POLL)

    async def expose(self, image_type: ImageType, *, cut_short: CutShortCallback | None = None) -> str:
        """Take one frame of ``image_type`` and return its VFS path; when cancelled, a science frame
        is stopped and kept if the camera can (then ``cut_short`` hears how much of its exposure
        time it got), anything else aborted."""
        what = f"{image_type.value} exposure"
        if self.stoppable is None or image_type is not ImageType.OBJECT:
            return await step(what, self.camera.grab_data(True, image_type), on_cancel=self.camera.abort)
        # In its own task: cancelling the script must not cancel the exposure, which reads out.
        stoppable = self.stoppable
        grab = asyncio.ensure_future(self.camera.grab_data(True, image_type))
        try:
            return await step(what, asyncio.shield(grab))
        except asyncio.CancelledError:
            await quietly(
                "stop the exposure and keep the frame",
                lambda: self._stop_and_keep(stoppable, grab, cut_short),
            )
            raise

    async def _stop_and_keep(
        self, stoppable: IStoppableExposure, grab: asyncio.Future[str], cut_short: CutShortCallback | None
    ) -> None:
        # Only light being collected is worth keeping; a frame not yet begun (the call may still be
        # on its way) or already reading out is aborted, as it always was, so closing never waits.
        exposing = await self.camera.get_exposure_status() is ExposureStatus.EXPOSING
        if exposing:
            # Asked right before the stop: the camera's own count, as its EXPTIME will say.
            fraction = min(1.0, max(0.0, await self.camera.get_exposure_progress() / 100.0))
            try:
                await stoppable.stop_exposure()
            except NotSupportedError:  # this device cannot after all (Alpaca's CanStopExposure)
                exposing = False
        if not exposing:
            grab.cancel()
            await self.camera.abort()
            await asyncio.wait({grab})
            return
        await asyncio.wait({grab})
        log.info("kept the interrupted exposure: %s", grab.result())  # a failure: quietly() logs it
        if cut_short is not None:
            await cut_short(fraction)
