"""An Alpaca SafetyMonitor as a weather station whose one sensor, ``safe``, is the device's IsSafe.

The module polls ``IsSafe`` like any weather station polls its sensors (every ``interval`` clock
seconds, stale readings count as unsafe) and reports it as the ``safe`` sensor (1 safe, 0 unsafe).
The Weather module takes it as one input among its stations and checks, so a safety monitor can
close the roof by itself or together with other sensors::

    # weather.yaml
    stations:
      safety: {class: nightcrew.modules.weather.ModuleStation, module: safetymonitor}
    checks:
      safety.safe: {class: nightcrew.weather.Boolean, good_when: true}

Example (``examples/alpaca/safetymonitor.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaSafetyMonitor
    server: http://127.0.0.1:11111
    device_number: 0
    interval: 10
"""

from __future__ import annotations

from nightcrew.interfaces import WeatherSensor
from nightcrew.modules.alpaca.checked import CheckedGets
from nightcrew.modules.weatherstation import BaseWeatherStation

__all__ = ["AlpacaSafetyMonitor"]


class AlpacaSafetyMonitor(CheckedGets, BaseWeatherStation):
    """A safety monitor; good weather means a fresh IsSafe that is true.

    Args:
        **kwargs: Alpaca options (``server``, ``device_number``, ...), ``interval`` (clock seconds
            between two readings) and module options.
    """

    device_type = "safetymonitor"

    async def _hw_read_sensors(self) -> dict[WeatherSensor, float | None]:
        safe = await self._get_flag("issafe")
        return {WeatherSensor.SAFE: 1.0 if safe else 0.0}

    async def is_weather_good(self) -> bool:
        safe = self._value(WeatherSensor.SAFE)
        return safe is not None and safe >= 0.5
