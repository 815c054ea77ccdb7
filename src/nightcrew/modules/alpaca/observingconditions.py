"""A weather station on an Alpaca ObservingConditions device.

At every (re)connect the module asks each ObservingConditions property once; those the device does
not implement (NotImplemented) are left out, the others are polled every ``interval`` clock
seconds. A property without a value yet (ValueNotSet) reads as None. Units become nightcrew's
(:class:`~nightcrew.interfaces.WeatherSensor`):

================  ===========================  ===============================
Alpaca property   unit there                   nightcrew sensor
================  ===========================  ===============================
Temperature       °C                           temperature
Humidity          %                            humidity
Pressure          hPa                          pressure
WindSpeed         m/s                          wind_speed (km/h, x 3.6)
WindDirection     degrees east of north        wind_direction
RainRate          mm/h                         rain (1 when > 0, else 0)
SkyTemperature    °C                           sky_temperature
DewPoint          °C                           dew_point
SkyQuality        mag/arcsec²                  sky_brightness
================  ===========================  ===============================

CloudCover, SkyBrightness (lux), StarFWHM and WindGust have no nightcrew sensor and are not read.

Example (``examples/alpaca/observingconditions.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaObservingConditions
    server: http://127.0.0.1:11111
    device_number: 0
    interval: 30
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from typing import Any

from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import WeatherSensor
from nightcrew.modules.alpaca.checked import CheckedGets
from nightcrew.modules.weatherstation import BaseWeatherStation

__all__ = ["SENSORS", "AlpacaObservingConditions"]

log = logging.getLogger(__name__)


def _same(value: float) -> float:
    return value


#: Alpaca property (URL member) → (nightcrew sensor, conversion into its unit).
SENSORS: dict[str, tuple[WeatherSensor, Callable[[float], float]]] = {
    "temperature": (WeatherSensor.TEMPERATURE, _same),
    "humidity": (WeatherSensor.HUMIDITY, _same),
    "pressure": (WeatherSensor.PRESSURE, _same),
    "windspeed": (WeatherSensor.WIND_SPEED, lambda metres_per_second: metres_per_second * 3.6),
    "winddirection": (WeatherSensor.WIND_DIRECTION, _same),
    "rainrate": (WeatherSensor.RAIN, lambda millimetres_per_hour: 1.0 if millimetres_per_hour > 0 else 0.0),
    "skytemperature": (WeatherSensor.SKY_TEMPERATURE, _same),
    "dewpoint": (WeatherSensor.DEW_POINT, _same),
    "skyquality": (WeatherSensor.SKY_BRIGHTNESS, _same),
}


class AlpacaObservingConditions(CheckedGets, BaseWeatherStation):
    """The sensors of an ObservingConditions device as a weather station.

    Args:
        **kwargs: Alpaca options (``server``, ``device_number``, ...), ``interval`` (clock seconds
            between two readings) and module options.
    """

    device_type = "observingconditions"

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._members: list[str] = []

    async def _on_connected(self) -> None:
        await super()._on_connected()
        found = []
        for member in SENSORS:
            try:
                await self._get(member)
            except NotSupportedError:
                continue
            except InvalidArgumentError:
                pass  # ValueNotSet: the sensor exists but has no value yet
            found.append(member)
        if not found:
            log.warning("%s: %s implements none of %s", self.name, self.device.name, ", ".join(SENSORS))
        self._members = found

    async def _read(self, member: str) -> float | None:
        try:
            value = await self._get_number(member)
        except InvalidArgumentError:
            return None  # ValueNotSet
        return SENSORS[member][1](value)

    async def _hw_read_sensors(self) -> dict[WeatherSensor, float | None]:
        values = await asyncio.gather(*(self._read(member) for member in self._members))
        return {SENSORS[member][0]: value for member, value in zip(self._members, values, strict=True)}
