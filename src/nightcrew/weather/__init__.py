"""Weather evaluation, pure: readings, evaluators, checks and the good-weather gate.

No comm, no clock, no I/O: the Weather module (:mod:`nightcrew.modules.weather`) feeds readings
and clock times in and announces what comes out. See :mod:`nightcrew.weather._evaluators` for
what each evaluator does.
"""

from nightcrew.weather._checks import CheckResult, SensorCheck
from nightcrew.weather._evaluators import DEFAULT_MAX_AGE, Boolean, Evaluator, Schmitt, Switch, Valid, Verdict
from nightcrew.weather._formats import json_pointer, last_csv_row, parse_number, parse_time
from nightcrew.weather._gate import GoodWeatherGate, WeatherChange
from nightcrew.weather._readings import Reading, average_reading, latest_reading

__all__ = [
    "DEFAULT_MAX_AGE",
    "Boolean",
    "CheckResult",
    "Evaluator",
    "GoodWeatherGate",
    "Reading",
    "Schmitt",
    "SensorCheck",
    "Switch",
    "Valid",
    "Verdict",
    "WeatherChange",
    "average_reading",
    "json_pointer",
    "last_csv_row",
    "latest_reading",
    "parse_number",
    "parse_time",
]
