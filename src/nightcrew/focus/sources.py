"""Where a focus model's temperature variables come from, as checked configuration.

Each model variable names a module and a reading there::

    T_mirror: {module: telescope, sensor: mirror}        # ITemperatures.get_temperatures()["mirror"]
    temp: {module: weather, weather_sensor: temperature}  # IWeather.get_sensor_value(station, sensor)
    temp: {module: weather, weather_sensor: temperature, station: roofstation}

For a weather sensor, ``station`` defaults to the module's name (a weather station answers for
itself; a weather aggregator needs the station's name).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.interfaces.enums import WeatherSensor

__all__ = ["TemperatureSource", "source_from_config", "sources_from_config"]

_KEYS = {"module", "sensor", "weather_sensor", "station"}


@dataclass(frozen=True)
class TemperatureSource:
    """One variable's reading: ``sensor`` of ITemperatures, or ``weather_sensor`` of IWeather."""

    module: str
    sensor: str | None = None
    weather_sensor: WeatherSensor | None = None
    station: str | None = None

    def describe(self) -> str:
        if self.weather_sensor is not None:
            return f"{self.module}: weather {self.station or self.module}/{self.weather_sensor.value}"
        return f"{self.module}: temperature {self.sensor}"


def sources_from_config(config: Mapping[str, Any], key: str) -> dict[str, TemperatureSource]:
    """Variable → source; ConfigError naming ``key.<variable>`` for the first bad entry."""
    return {
        str(variable): source_from_config(entry, f"{key}.{variable}") for variable, entry in config.items()
    }


def source_from_config(entry: object, where: str) -> TemperatureSource:
    """One source from its mapping; ConfigError naming ``where`` when it is bad."""
    if not isinstance(entry, Mapping):
        raise ConfigError(f"expected a mapping like {{module: NAME, sensor: NAME}}, got {entry!r}", key=where)
    unknown = sorted(set(entry) - _KEYS)
    if unknown:
        raise ConfigError(f"unknown keys {unknown}; known: {', '.join(sorted(_KEYS))}", key=where)
    module = entry.get("module")
    if not isinstance(module, str) or not module:
        raise ConfigError("needs 'module': the name of the module to read from", key=where)
    sensor, weather = entry.get("sensor"), entry.get("weather_sensor")
    if (sensor is None) == (weather is None):
        raise ConfigError("give exactly one of 'sensor' (ITemperatures) or 'weather_sensor'", key=where)
    if weather is not None:
        try:
            kind = WeatherSensor(weather)
        except ValueError:
            known = ", ".join(s.value for s in WeatherSensor)
            raise ConfigError(f"unknown weather sensor {weather!r}; known: {known}", key=where) from None
        station = entry.get("station")
        return TemperatureSource(
            module, weather_sensor=kind, station=None if station is None else str(station)
        )
    if "station" in entry:
        raise ConfigError("'station' belongs to a 'weather_sensor' source", key=where)
    return TemperatureSource(module, sensor=str(sensor))
