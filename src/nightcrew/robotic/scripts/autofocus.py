"""AUTO_FOCUS configurations: a focus series by an IAutoFocus module, per instrument config."""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import IAutoFocus, IFilters, ITelescope
from nightcrew.robotic.runner import ProgressCallback, ProgressReporter, Script, the_configuration
from nightcrew.robotic.scripts._instrument import FILTER_ELEMENT
from nightcrew.robotic.scripts._steps import step
from nightcrew.robotic.scripts.focus_fields import FocusFields, catalogue_rules
from nightcrew.robotic.tasks import AnyTarget, ConfigurationType, InstrumentConfig, Task, target_radec

__all__ = ["AutoFocusScript", "focus_step"]

log = logging.getLogger(__name__)


def focus_step(config: InstrumentConfig, default: float) -> float:
    """Focuser step (mm) between frames: ``extra_params.step``, else ``focus_range`` / (count - 1).

    Raises:
        InvalidArgumentError: The step is not a positive number.
    """
    params = config.extra_params
    if "step" in params:
        value = params["step"]
    elif "focus_range" in params:
        span = params["focus_range"]
        value = span / max(config.exposure_count - 1, 1) if _number(span) else span
    else:
        value = default
    if not _number(value) or not value > 0:
        raise InvalidArgumentError(f"the focus step must be a positive number of mm, got {value!r}")
    return float(value)


def _number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


class AutoFocusScript(Script):
    """Finds the best focus: slew to the target (if any), set the filter, run the focus series.

    A configuration without a target focuses where the telescope points, or, with ``field``, on
    the nearest catalogue field that meets those rules (see
    :class:`~nightcrew.astro.star_fields.StarFieldRules`), tracked.

    Each instrument config is one series of ``exposure_count`` frames of ``exposure_time`` s,
    ``focus_step`` apart (``extra_params.step`` in mm, or ``extra_params.focus_range`` in mm across
    the series). The focus module leaves the focuser at the best focus. Progress is reported after
    each series (the module takes the frames).

    Args:
        focus: Module offering IAutoFocus.
        telescope: Module offering ITelescope, for configurations with a target; None: never slew.
        filters: Module offering IFilters; None: no filter wheel.
        step: Step in mm when the task names none.
        field: Rules for choosing a field near the pointing when the task has no target
            (``radius``, ``magnitudes``, ``min_stars``, ``min_altitude``, ``max_distance``); None:
            focus where the telescope points.
    """

    def __init__(
        self,
        *,
        focus: str | IAutoFocus = "focus",
        telescope: str | ITelescope | None = "telescope",
        filters: str | IFilters | None = "filters",
        step: float = 0.05,
        field: dict[str, Any] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not step > 0:
            raise ConfigError(f"must be > 0 mm, got {step}", key="step")
        self._focus, self._telescope, self._filters, self._step = focus, telescope, filters, float(step)
        self._field = None if field is None else catalogue_rules(field, "field")

    async def can_run(self, task: Task) -> bool:
        config = the_configuration(task)
        if config.type is not ConfigurationType.AUTO_FOCUS or not await self.offers(self._focus, IAutoFocus):
            return False
        pointed = config.target is not None or self._field is not None
        if pointed and not await self.offers(self._telescope, ITelescope):
            return False
        wanted = {
            c.optical_elements[FILTER_ELEMENT]
            for c in config.instrument_configs
            if FILTER_ELEMENT in c.optical_elements
        }
        if wanted:
            wheel = await self.optional_proxy(self._filters, IFilters)
            return wheel is not None and wanted <= set(await wheel.list_filters())
        return True

    async def run(self, task: Task, progress: ProgressCallback) -> None:
        config = the_configuration(task)
        if config.type is not ConfigurationType.AUTO_FOCUS:
            raise NotSupportedError(f"{type(self).__name__} runs AUTO_FOCUS, not {config.type}")
        steps = [focus_step(c, self._step) for c in config.instrument_configs]  # bad steps fail first
        focus = await self.proxy(self._focus, IAutoFocus)
        if config.target is not None or self._field is not None:
            if self._telescope is None:
                raise NotSupportedError("the focus target needs a telescope, but none is configured")
            telescope = await self.proxy(self._telescope, ITelescope)
            name, ra, dec = await self._where(config.target, telescope)
            await step(f"slew to {name}", telescope.move_radec(ra, dec), on_cancel=telescope.stop_motion)
        reporter = ProgressReporter(task, progress)
        for index, (instrument_config, focus_step_mm) in enumerate(
            zip(config.instrument_configs, steps, strict=True)
        ):
            if reporter.remaining(index) == 0:
                continue  # this series ran in an earlier attempt
            filter_name = instrument_config.optical_elements.get(FILTER_ELEMENT)
            if filter_name is not None:
                wheel = await self.optional_proxy(self._filters, IFilters)
                if wheel is None:
                    raise NotSupportedError(
                        f"filter {filter_name} requested, but no filter wheel is available"
                    )
                await step(f"set filter {filter_name}", wheel.set_filter(filter_name))
            count, exposure_time = instrument_config.exposure_count, instrument_config.exposure_time
            best, error = await step(
                f"focus series of {count} x {exposure_time:g} s, {focus_step_mm:g} mm apart",
                focus.auto_focus(count, focus_step_mm, exposure_time),
                on_cancel=focus.abort,
            )
            log.info("best focus %.4f +- %.4f mm", best, error)
            await reporter.add(index, count)

    async def _where(self, target: AnyTarget | None, telescope: ITelescope) -> tuple[str, float, float]:
        """(name, ra, dec) to focus on: the task's target (a moving one where it is now), else a
        catalogue field near the pointing."""
        if target is not None:
            return (target.name, *target_radec(target, self.site, self.clock.time()))
        assert self._field is not None  # run() asks only with a target or field rules
        if self.site is None:
            raise NotSupportedError("choosing a focus field needs the observatory's site")
        near = await step("read the pointing", telescope.get_radec())
        field = await FocusFields(self._field, self.site).choose(near, self.clock.time())
        return f"the focus field at ra {field.ra:.3f}°, dec {field.dec:.3f}°", field.ra, field.dec
