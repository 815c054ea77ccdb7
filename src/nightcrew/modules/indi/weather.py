"""A weather station behind an INDI driver: ``WEATHER_PARAMETERS`` as sensors, the driver's overall
verdict (``WEATHER_STATUS`` state; Alert = danger) as the ``safe`` sensor.

Feed it to the Weather module like any station (``ModuleStation``); ``safe`` is the evaluator
input for INDI's own verdict::

    stations:
      indi: {class: nightcrew.modules.weather.ModuleStation, module: indiweather}
    checks:
      indi.safe: {class: nightcrew.weather.Boolean, good_when: true}
      indi.rain: {class: nightcrew.weather.Boolean, good_when: false}

Example (``examples/indi/weather.yaml``)::

    class: nightcrew.modules.indi.IndiWeather
    host: 192.168.1.20
    device: Weather Simulator
    interval: 30
"""

from __future__ import annotations

from nightcrew.bridges.indi import PropertyState
from nightcrew.interfaces import WeatherSensor
from nightcrew.modules.indi.link import IndiModule
from nightcrew.modules.weatherstation import BaseWeatherStation

__all__ = ["INDI_SENSORS", "IndiWeather"]

_PARAMETERS = "WEATHER_PARAMETERS"
_STATUS = "WEATHER_STATUS"

#: INDI weather parameter → nightcrew sensor (INDI's units match: °C, %, hPa, km/h, degrees).
INDI_SENSORS: dict[str, WeatherSensor] = {
    "WEATHER_TEMPERATURE": WeatherSensor.TEMPERATURE,
    "WEATHER_HUMIDITY": WeatherSensor.HUMIDITY,
    "WEATHER_PRESSURE": WeatherSensor.PRESSURE,
    "WEATHER_WIND_SPEED": WeatherSensor.WIND_SPEED,
    "WEATHER_WIND_DIRECTION": WeatherSensor.WIND_DIRECTION,
    "WEATHER_DEWPOINT": WeatherSensor.DEW_POINT,
    "WEATHER_SKY_TEMPERATURE": WeatherSensor.SKY_TEMPERATURE,
    "WEATHER_SKY_BRIGHTNESS": WeatherSensor.SKY_BRIGHTNESS,
}
#: Parameters that mean rain when above zero (mm/h or a rain flag).
_RAIN = ("WEATHER_RAIN_HOUR", "WEATHER_RAIN", "WEATHER_PRECIPITATION")


class IndiWeather(IndiModule, BaseWeatherStation):
    """An INDI weather station.

    Args:
        **kwargs: INDI options (``host``, ``port``, ``device`` ...) and station options (``interval``).
    """

    indi_needs = (_PARAMETERS,)

    async def _on_indi_ready(self) -> None:
        await self.read_now()  # fresh readings right after every (re)connection

    async def _hw_read_sensors(self) -> dict[WeatherSensor, float | None]:
        if not self._indi.readable:
            return {}  # nothing known (bad weather) until the device is there; read again then
        parameters = self._indi.vector(_PARAMETERS)
        readings: dict[WeatherSensor, float | None] = {}
        for name in parameters.members:
            if name in INDI_SENSORS:
                readings[INDI_SENSORS[name]] = parameters.number(name)
            elif name in _RAIN:
                rain = 1.0 if parameters.number(name) > 0 else 0.0
                readings[WeatherSensor.RAIN] = max(rain, readings.get(WeatherSensor.RAIN) or 0.0)
        if self._indi.has(_STATUS):
            alert = self._indi.vector(_STATUS).state is PropertyState.ALERT
            readings[WeatherSensor.SAFE] = 0.0 if alert else 1.0
        return readings

    async def is_weather_good(self) -> bool:
        safe = self._value(WeatherSensor.SAFE)
        return await super().is_weather_good() and safe != 0.0
