"""SKY_FLAT configurations: twilight flats by an IFlatField module, per instrument config."""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.errors import NotSupportedError
from nightcrew.interfaces import Binning, IFlatField
from nightcrew.robotic.runner import ProgressCallback, ProgressReporter, Script, the_configuration
from nightcrew.robotic.scripts._instrument import FILTER_ELEMENT
from nightcrew.robotic.scripts._steps import step
from nightcrew.robotic.tasks import ConfigurationType, Task

__all__ = ["SkyFlatScript"]

log = logging.getLogger(__name__)


class SkyFlatScript(Script):
    """Takes sky flats: ``exposure_count`` flats per instrument config in its filter and binning.

    The flat-field module points the telescope, chooses the exposure times from the sky (the
    task's are only a first guess) and waits for or stops at the right twilight; it may take fewer
    frames than asked when the twilight ends, which the progress then shows.

    Args:
        flatfield: Module offering IFlatField.
    """

    def __init__(self, *, flatfield: str | IFlatField = "flatfield", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._flatfield = flatfield

    async def can_run(self, task: Task) -> bool:
        config = the_configuration(task)
        return config.type is ConfigurationType.SKY_FLAT and await self.offers(self._flatfield, IFlatField)

    async def run(self, task: Task, progress: ProgressCallback) -> None:
        config = the_configuration(task)
        if config.type is not ConfigurationType.SKY_FLAT:
            raise NotSupportedError(f"{type(self).__name__} runs SKY_FLAT, not {config.type}")
        flatfield = await self.proxy(self._flatfield, IFlatField)
        reporter = ProgressReporter(task, progress)
        for index, instrument_config in enumerate(config.instrument_configs):
            count = reporter.remaining(index)
            if count == 0:
                continue  # taken in an earlier attempt
            filter_name = instrument_config.optical_elements.get(FILTER_ELEMENT)
            binning = instrument_config.binning
            taken, exposure = await step(
                f"{count} sky flats in {filter_name or 'the current filter'}",
                flatfield.flat_field(count, Binning(binning, binning), filter_name),
                on_cancel=flatfield.abort,
            )
            if taken < count:
                log.warning("only %d of %d flats in %s (twilight over?)", taken, count, filter_name)
            if taken > 0:
                await reporter.add(index, taken)
            log.info("%d flats, %.1f s exposed in total", taken, exposure)
