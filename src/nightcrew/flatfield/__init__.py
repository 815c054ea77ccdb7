"""Twilight flat fields, pure: exposure-time functions, the T_min/T_max control, pointing, scheduling
and fitting new exposure-time functions from a night's flats."""

from nightcrew.flatfield.control import (
    Decision,
    FlatExposureControl,
    FlatLimits,
    Twilight,
    twilight_from_altitudes,
)
from nightcrew.flatfield.exptime import NO_FILTER, ExposureTimeFunctions, binning_key, parse_binning
from nightcrew.flatfield.pointing import antisolar_position, dither_offset
from nightcrew.flatfield.schedule import FlatTask, last_taken_from_plain, prioritised, tasks_from_config
from nightcrew.flatfield.twilight_plan import PlannedFlats, TwilightPlanner, plan_twilight

__all__ = [
    "NO_FILTER",
    "Decision",
    "ExposureTimeFunctions",
    "FlatExposureControl",
    "FlatLimits",
    "FlatTask",
    "PlannedFlats",
    "Twilight",
    "TwilightPlanner",
    "antisolar_position",
    "binning_key",
    "dither_offset",
    "last_taken_from_plain",
    "parse_binning",
    "plan_twilight",
    "prioritised",
    "tasks_from_config",
    "twilight_from_altitudes",
]
