"""A SCRIPT configuration that runs a pointing series (configured as ``SCRIPT:<name>``)."""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.interfaces import IPointingSeries
from nightcrew.robotic.runner import ProgressCallback, Script, the_configuration
from nightcrew.robotic.scripts._steps import step
from nightcrew.robotic.tasks import ConfigurationType, Task

__all__ = ["PointingSeriesScript"]

log = logging.getLogger(__name__)


class PointingSeriesScript(Script):
    """Runs the pointing series of an IPointingSeries module; the CSV path goes to the log.

    Args:
        pointing: Module offering IPointingSeries.
    """

    def __init__(self, *, pointing: str | IPointingSeries = "pointing", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._pointing = pointing
        #: VFS path of the last series' measurements.
        self.last_result: str | None = None

    async def can_run(self, task: Task) -> bool:
        config = the_configuration(task)
        return config.type is ConfigurationType.SCRIPT and await self.offers(self._pointing, IPointingSeries)

    async def run(self, task: Task, progress: ProgressCallback) -> None:
        the_configuration(task)
        series = await self.proxy(self._pointing, IPointingSeries)
        self.last_result = await step(
            "pointing series", series.start_pointing_series(), on_cancel=series.abort
        )
        log.info("pointing series written to %s", self.last_result)
