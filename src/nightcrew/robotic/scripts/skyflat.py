"""SKY_FLAT configurations: twilight flats by an IFlatField module, per instrument config."""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.astro import sun_altitude_at
from nightcrew.errors import NotSupportedError
from nightcrew.flatfield import FlatTask, TwilightPlanner
from nightcrew.interfaces import Binning, IFlatField
from nightcrew.robotic.runner import (
    ProgressCallback,
    ProgressReporter,
    Script,
    ScriptError,
    the_configuration,
)
from nightcrew.robotic.scripts._instrument import FILTER_ELEMENT
from nightcrew.robotic.scripts._steps import step
from nightcrew.robotic.tasks import Configuration, ConfigurationType, Task

__all__ = ["SkyFlatScript"]

log = logging.getLogger(__name__)


class SkyFlatScript(Script):
    """Takes sky flats: ``exposure_count`` flats per instrument config in its filter and binning.

    The flat-field module points the telescope, chooses the exposure times from the sky (the
    task's are only a first guess) and waits for or stops at the right twilight; it may take fewer
    frames than asked when the twilight ends: the progress then shows them and the task fails with
    :class:`ScriptError` saying how many are missing (a retry takes only those).

    With the exposure-time ``functions`` (the FlatField module's, e.g. from a shared include
    file) the instrument configs are taken in the order the twilight planner gives
    (:mod:`nightcrew.flatfield.twilight_plan`, earlier instrument configs having priority): at dusk
    the filters needing long exposures first, before the sky is too dark for them, at dawn those
    needing short ones. Without, they are taken in the task's order.

    Args:
        flatfield: Module offering IFlatField.
        functions: Filter -> binning -> exposure time as a function of ``h``; None: task order.
        min_exposure, max_exposure: T_min and T_max, as configured for the flat-field module.
        overhead: Seconds per flat besides the exposure (read-out, pointing), for the plan.
    """

    def __init__(
        self,
        *,
        flatfield: str | IFlatField = "flatfield",
        functions: dict[str, dict[str, str]] | None = None,
        min_exposure: float = 1.0,
        max_exposure: float = 30.0,
        overhead: float = 10.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        self._flatfield = flatfield
        self._planner = (
            None
            if functions is None
            else TwilightPlanner(
                functions, min_exposure=min_exposure, max_exposure=max_exposure, overhead=overhead
            )
        )

    async def can_run(self, task: Task) -> bool:
        config = the_configuration(task)
        return config.type is ConfigurationType.SKY_FLAT and await self.offers(self._flatfield, IFlatField)

    async def run(self, task: Task, progress: ProgressCallback) -> None:
        config = the_configuration(task)
        if config.type is not ConfigurationType.SKY_FLAT:
            raise NotSupportedError(f"{type(self).__name__} runs SKY_FLAT, not {config.type}")
        flatfield = await self.proxy(self._flatfield, IFlatField)
        reporter = ProgressReporter(task, progress)
        for index in self._order(config, reporter):
            instrument_config = config.instrument_configs[index]
            count = reporter.remaining(index)
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
        missing = sum(reporter.remaining(i) for i in range(len(config.instrument_configs)))
        if missing > 0:
            # Not done: a task reported complete without its flats would hide that they are lacking.
            wanted = sum(c.exposure_count for c in config.instrument_configs)
            raise ScriptError(f"sky flats incomplete: {missing} of {wanted} missing (twilight over?)")

    def _order(self, config: Configuration, reporter: ProgressReporter) -> list[int]:
        """Indexes of the instrument configs with flats missing, in the order to take them."""
        missing = [i for i in range(len(config.instrument_configs)) if reporter.remaining(i) > 0]
        if self._planner is None or len(missing) < 2:
            return missing
        combinations = {
            i: FlatTask(
                config.instrument_configs[i].optical_elements.get(FILTER_ELEMENT),
                (config.instrument_configs[i].binning,) * 2,
                reporter.remaining(i),
            )
            for i in missing
        }
        index_of = {task.key: i for i, task in combinations.items()}
        if self.site is None or len(index_of) < len(missing):
            log.warning("cannot plan the flats (no site, or a filter and binning twice): task order")
            return missing
        try:
            plan = self._planner.plan(
                list(combinations.values()), sun_altitude_at(self.site), self.clock.time()
            )
        except ValueError as exc:  # e.g. no function for a filter: the flat-field module says so
            log.warning("cannot plan the flats (%s): task order", exc)
            return missing
        log.info(
            "flats planned: %s", ", ".join(f"{p.task.key}{'' if p.fits else ' (may not fit)'}" for p in plan)
        )
        return [index_of[planned.task.key] for planned in plan]
