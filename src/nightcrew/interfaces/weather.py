"""Weather: whether it is safe to open, and the measurements behind that verdict."""

from __future__ import annotations

from abc import abstractmethod
from dataclasses import dataclass
from datetime import datetime

from nightcrew.interfaces.base import Interface
from nightcrew.interfaces.enums import WeatherSensor

__all__ = ["IWeather", "SensorValue", "WeatherReport"]


@dataclass(frozen=True)
class SensorValue:
    """One measurement; units are those of :class:`WeatherSensor`. None if the sensor has no value."""

    time: datetime
    value: float | None


@dataclass(frozen=True)
class WeatherReport:
    """The current weather as the weather module sees it."""

    time: datetime
    good: bool
    #: WeatherSensor value (e.g. "humidity") → measurement, None where unavailable.
    sensors: dict[str, float | None]


class IWeather(Interface):
    """A weather module combining one or more stations into a verdict.

    A *station* is named as in the weather module's configuration (the keys of its ``stations:``,
    e.g. ``roof``; its ``checks`` name them as ``station.sensor``), not as a module.
    """

    @abstractmethod
    async def is_weather_good(self) -> bool:
        """Whether the weather allows the observatory to be open."""

    @abstractmethod
    async def get_current_weather(self) -> WeatherReport:
        """The verdict with the current measurements."""

    @abstractmethod
    async def get_sensor_value(self, station: str, sensor: WeatherSensor) -> SensorValue:
        """Latest ``sensor`` value at ``station`` (a key of the module's ``stations:``); None: no reading."""
