"""Bias and dark frames: the camera alone, no telescope, no filter, the roof may stay closed."""

from __future__ import annotations

from typing import Any

from nightcrew.errors import NotSupportedError
from nightcrew.interfaces import ICamera, ImageType
from nightcrew.robotic.runner import ProgressCallback, ProgressReporter, Script, the_configuration
from nightcrew.robotic.scripts._instrument import Instrument, instrument_supported
from nightcrew.robotic.tasks import ConfigurationType, Task

__all__ = ["CalibrationScript"]

_IMAGE_TYPES = {ConfigurationType.BIAS: ImageType.BIAS, ConfigurationType.DARK: ImageType.DARK}


class CalibrationScript(Script):
    """Takes BIAS or DARK frames: binning and (for darks) exposure time per instrument config.

    Nothing moves: the telescope is not slewed and filters named in the task are ignored (no
    light reaches the detector of a dark anyway).

    Args:
        camera: Module offering ICamera (IExposureTime for darks, IBinning if binning is asked for).
    """

    def __init__(self, *, camera: str | ICamera = "camera", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._camera = camera

    async def can_run(self, task: Task) -> bool:
        config = the_configuration(task)
        if config.type not in _IMAGE_TYPES:
            return False
        timed = config.type is ConfigurationType.DARK
        return await instrument_supported(self, self._camera, None, config, timed=timed, use_filters=False)

    async def run(self, task: Task, progress: ProgressCallback) -> None:
        config = the_configuration(task)
        image_type = _IMAGE_TYPES.get(config.type)
        if image_type is None:
            raise NotSupportedError(f"{type(self).__name__} runs BIAS and DARK, not {config.type}")
        instrument = await Instrument.connect(self, self._camera, None)
        reporter = ProgressReporter(task, progress)
        for index, instrument_config in enumerate(config.instrument_configs):
            missing = reporter.remaining(index)
            if missing == 0:
                continue
            await instrument.set_up(instrument_config, timed=image_type is ImageType.DARK, use_filter=False)
            for _ in range(missing):
                await instrument.expose(image_type)
                await reporter.add(index)
