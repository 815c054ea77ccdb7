"""Weather stations: the device that measures. Deciding whether to close is the Weather module's job.

A station polls its sensors every ``interval`` clock seconds and answers from the latest readings.
Its own verdict (``is_weather_good``) is only what the hardware itself knows: readings are fresh
and the rain sensor is dry. Stale readings count as bad (fail safe).
"""

from __future__ import annotations

import logging
import math
from abc import abstractmethod
from datetime import UTC, datetime
from typing import Any

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.interfaces import (
    ITemperatures,
    IWeather,
    ModuleState,
    SensorValue,
    WeatherReport,
    WeatherSensor,
)
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.module import Module

__all__ = ["BaseWeatherStation"]

log = logging.getLogger(__name__)

#: Readings older than this many polling intervals are stale.
_STALE_INTERVALS = 3.0


class BaseWeatherStation(Module, IWeather, ITemperatures):
    """A weather station; a driver implements :meth:`_hw_read_sensors`.

    Args:
        interval: Clock seconds between two readings, > 0.
        **kwargs: Module options.
    """

    def __init__(self, *, interval: Period = 30.0, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        if not interval > 0:
            raise ConfigError(f"must be > 0 seconds, got {interval}", key="interval")
        self._interval = float(interval)
        self._readings: dict[WeatherSensor, float | None] = {}
        self._read_at = -math.inf
        self.add_background_task(self._poll_loop)

    @abstractmethod
    async def _hw_read_sensors(self) -> dict[WeatherSensor, float | None]:
        """Read every sensor the station has; None for one that has no value now."""

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        try:  # answer from real readings right away; a failure here is retried by the loop
            await self.read_now()
        except Exception:
            log.exception("%s: first reading failed", self.name)

    async def _poll_loop(self) -> None:
        while True:
            await self.clock.sleep(self._interval)
            await self.read_now()

    async def read_now(self) -> None:
        """Read the sensors and keep the readings (also what the polling loop does)."""
        self._readings = dict(await self._hw_read_sensors())
        self._read_at = self.clock.time()

    @property
    def _fresh(self) -> bool:
        return self.clock.time() - self._read_at <= _STALE_INTERVALS * self._interval

    def _value(self, sensor: WeatherSensor) -> float | None:
        return self._readings.get(sensor) if self._fresh else None

    # --- IWeather ------------------------------------------------------------------------------

    async def is_weather_good(self) -> bool:
        rain = self._value(WeatherSensor.RAIN)
        return self._fresh and rain is not None and rain < 0.5

    async def get_current_weather(self) -> WeatherReport:
        return WeatherReport(
            time=self._reading_time(),
            good=await self.is_weather_good(),
            sensors={sensor.value: self._value(sensor) for sensor in self._readings},
        )

    async def get_sensor_value(self, station: str, sensor: WeatherSensor) -> SensorValue:
        if station not in ("", self.name):
            raise InvalidArgumentError(f"this is weather station '{self.name}', not '{station}'")
        sensor = WeatherSensor(sensor)
        if self._readings and sensor not in self._readings:
            have = ", ".join(s.value for s in self._readings)
            raise InvalidArgumentError(f"station '{self.name}' has no {sensor.value} sensor; it has: {have}")
        return SensorValue(time=self._reading_time(), value=self._value(sensor))

    async def get_temperatures(self) -> dict[str, float]:
        ambient = self._value(WeatherSensor.TEMPERATURE)
        return {} if ambient is None else {"ambient": ambient}

    def _reading_time(self) -> datetime:
        when = self._read_at if math.isfinite(self._read_at) else self.clock.time()
        return datetime.fromtimestamp(when, tz=UTC)
