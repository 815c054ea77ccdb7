"""How long a request takes: exposures, read-outs and the overheads around them.

The :class:`OverheadModel` says what each step costs; :func:`estimate_duration` adds them up::

    request    = request_setup_s + sum(configuration)
    configuration = configuration_setup_s
                  + acquisition_s      (acquisition mode not OFF)
                  + guiding_setup_s    (guiding mode ON)
                  + body
    body       = sum over instrument configs of
                     filter_change_s   (first series, or optical elements differ from the previous)
                   + exposure_count * (exposure_time + readout(binning) + per_exposure_s)
                 REPEAT_EXPOSE: repeat_duration; SCRIPT: extra_params.duration (+ any series)

The defaults suit a small robotic telescope (the simulated 0.4 m); give a site its own model in
its configuration.
"""

from __future__ import annotations

from dataclasses import dataclass

from pydantic import Field

from nightcrew.robotic.tasks._base import Integer, Number, TaskModel
from nightcrew.robotic.tasks._configuration import (
    AcquisitionMode,
    Configuration,
    ConfigurationType,
    GuidingMode,
    InstrumentConfig,
)
from nightcrew.robotic.tasks._request import Request

__all__ = [
    "DEFAULT_OVERHEADS",
    "DurationEstimate",
    "OverheadModel",
    "configuration_duration",
    "estimate_duration",
]


class OverheadModel(TaskModel):
    """Seconds spent around the exposures.

    Args:
        request_setup_s: Once per request: slew to the first target, settle, open the instrument.
        configuration_setup_s: Once per configuration: slew between targets, instrument set-up.
        acquisition_s: Per configuration whose acquisition mode is not OFF.
        guiding_setup_s: Per configuration that guides: find a guide star, close the loop.
        filter_change_s: Per change of optical elements.
        readout_s: Read-out of one unbinned frame.
        readout_by_binning_s: Read-out for particular binnings (e.g. ``{2: 1.0}``); others use
            ``readout_s``.
        per_exposure_s: Per exposure besides the read-out: shutter, headers, writing the file.
    """

    request_setup_s: Number = Field(default=90.0, ge=0.0)
    configuration_setup_s: Number = Field(default=15.0, ge=0.0)
    acquisition_s: Number = Field(default=60.0, ge=0.0)
    guiding_setup_s: Number = Field(default=30.0, ge=0.0)
    filter_change_s: Number = Field(default=3.0, ge=0.0)
    readout_s: Number = Field(default=2.0, ge=0.0)
    readout_by_binning_s: dict[Integer, Number] = Field(default_factory=dict)
    per_exposure_s: Number = Field(default=1.0, ge=0.0)

    def readout(self, binning: int) -> float:
        """Seconds to read out one frame binned ``binning`` x ``binning``."""
        return self.readout_by_binning_s.get(binning, self.readout_s)


#: The overheads used when none are given.
DEFAULT_OVERHEADS = OverheadModel()


@dataclass(frozen=True)
class DurationEstimate:
    """How long a request takes, split into its fixed set-up and its configurations (seconds)."""

    setup_s: float
    configurations_s: tuple[float, ...]

    @property
    def total_s(self) -> float:
        """The whole request."""
        return self.setup_s + sum(self.configurations_s)


def estimate_duration(request: Request, overheads: OverheadModel = DEFAULT_OVERHEADS) -> DurationEstimate:
    """The time ``request`` takes with ``overheads``."""
    return DurationEstimate(
        setup_s=overheads.request_setup_s,
        configurations_s=tuple(configuration_duration(c, overheads) for c in request.configurations),
    )


def configuration_duration(
    configuration: Configuration, overheads: OverheadModel = DEFAULT_OVERHEADS
) -> float:
    """Seconds ``configuration`` takes, its own set-up included."""
    seconds = overheads.configuration_setup_s
    if configuration.acquisition_config.mode is not AcquisitionMode.OFF:
        seconds += overheads.acquisition_s
    if configuration.guiding_config.mode is GuidingMode.ON:
        seconds += overheads.guiding_setup_s
    series = _series_duration(configuration.instrument_configs, overheads)
    if configuration.type is ConfigurationType.REPEAT_EXPOSE and configuration.repeat_duration is not None:
        # The cycle repeats until repeat_duration is used up, but at least once.
        return seconds + max(configuration.repeat_duration, series)
    if configuration.type is ConfigurationType.SCRIPT:
        return seconds + configuration.script_duration + series
    return seconds + series


def _series_duration(instrument_configs: tuple[InstrumentConfig, ...], overheads: OverheadModel) -> float:
    seconds = 0.0
    previous: dict[str, str] | None = None
    for instrument_config in instrument_configs:
        if instrument_config.optical_elements and instrument_config.optical_elements != previous:
            seconds += overheads.filter_change_s
        previous = instrument_config.optical_elements
        per_exposure = (
            instrument_config.exposure_time
            + overheads.readout(instrument_config.binning)
            + overheads.per_exposure_s
        )
        seconds += instrument_config.exposure_count * per_exposure
    return seconds
