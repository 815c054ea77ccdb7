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

A retried task takes only what an interrupted attempt left (:class:`TaskProgress`): given the
progress, :func:`estimate_duration` counts only the exposures still missing, leaves out
configurations with nothing left, and for a REPEAT_EXPOSE the repeat time left (plus the first
cycle if it was not completed) - the same rules the runner and the scripts resume by.

The defaults suit a small robotic telescope (the simulated 0.4 m); give a site its own model in
its configuration.
"""

from __future__ import annotations

from collections.abc import Sequence
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
from nightcrew.robotic.tasks._state import TaskProgress

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


def estimate_duration(
    request: Request, overheads: OverheadModel = DEFAULT_OVERHEADS, *, progress: TaskProgress | None = None
) -> DurationEstimate:
    """The time ``request`` takes with ``overheads``.

    With ``progress`` recorded by an earlier, interrupted attempt, the time a retry takes: what is
    left of each configuration (0 for one the runner skips). The request's set-up stays: a retry
    slews and sets up again.
    """
    done = TaskProgress() if progress is None else progress
    return DurationEstimate(
        setup_s=overheads.request_setup_s,
        configurations_s=tuple(
            _time_left(request, index, done, overheads) for index in range(len(request.configurations))
        ),
    )


def configuration_duration(
    configuration: Configuration, overheads: OverheadModel = DEFAULT_OVERHEADS
) -> float:
    """Seconds ``configuration`` takes, its own set-up included."""
    counts = [instrument_config.exposure_count for instrument_config in configuration.instrument_configs]
    return _configuration_seconds(configuration, overheads, counts, configuration.repeat_duration)


def _time_left(request: Request, index: int, done: TaskProgress, overheads: OverheadModel) -> float:
    """Seconds configuration ``index`` takes after ``done``, as the runner and scripts resume it."""
    configuration = request.configurations[index]
    if not done.exposures_done:
        return configuration_duration(configuration, overheads)
    if done.nothing_left(request, index):
        return 0.0  # the runner skips it
    if configuration.type is ConfigurationType.REPEAT_EXPOSE:
        # A completed first cycle is not forced again; otherwise the script starts a whole cycle.
        first_cycle_done = done.configuration_complete(request, index)
        counts = [0 if first_cycle_done else c.exposure_count for c in configuration.instrument_configs]
        return _configuration_seconds(configuration, overheads, counts, done.repeat_time_left(request, index))
    counts = [done.remaining(request, index, i) for i in range(len(configuration.instrument_configs))]
    return _configuration_seconds(configuration, overheads, counts, None)


def _configuration_seconds(
    configuration: Configuration, overheads: OverheadModel, counts: Sequence[int], repeat_s: float | None
) -> float:
    """Seconds of ``configuration`` taking ``counts`` exposures of its instrument configs (a
    REPEAT_EXPOSE: cycling for at least ``repeat_s``), its own set-up included."""
    seconds = overheads.configuration_setup_s
    if configuration.acquisition_config.mode is not AcquisitionMode.OFF:
        seconds += overheads.acquisition_s
    if configuration.guiding_config.mode is GuidingMode.ON:
        seconds += overheads.guiding_setup_s
    series = _series_duration(configuration.instrument_configs, counts, overheads)
    if configuration.type is ConfigurationType.REPEAT_EXPOSE and repeat_s is not None:
        # The cycle repeats until its time (repeat_duration, or what a retry has left) is used up,
        # but at least once.
        return seconds + max(repeat_s, series)
    if configuration.type is ConfigurationType.SCRIPT:
        return seconds + configuration.script_duration + series
    return seconds + series


def _series_duration(
    instrument_configs: tuple[InstrumentConfig, ...], counts: Sequence[int], overheads: OverheadModel
) -> float:
    seconds = 0.0
    previous: dict[str, str] | None = None
    for instrument_config, count in zip(instrument_configs, counts, strict=True):
        if count == 0:
            continue  # a retry does not set up an instrument config it has all frames of
        if instrument_config.optical_elements and instrument_config.optical_elements != previous:
            seconds += overheads.filter_change_s
        previous = instrument_config.optical_elements
        per_exposure = (
            instrument_config.exposure_time
            + overheads.readout(instrument_config.binning)
            + overheads.per_exposure_s
        )
        seconds += count * per_exposure
    return seconds
