"""Reading one configured temperature (a :class:`~nightcrew.focus.sources.TemperatureSource`) through a proxy.

Shared by the focus model (its formula's variables) and the mastermind (its refocus temperature), so
a sensor name that the module does not have is one clear error in both, never a silent None.
"""

from __future__ import annotations

import math

from nightcrew.errors import ModuleError
from nightcrew.focus.sources import TemperatureSource
from nightcrew.interfaces import ITemperatures, IWeather
from nightcrew.object import Object

__all__ = ["read_temperature"]


async def read_temperature(host: Object, source: TemperatureSource) -> float:
    """The temperature (°C) ``source`` names, read through ``host``'s proxies.

    Raises:
        ModuleError: The module has no such sensor, or no finite reading now (naming the source).
        NightcrewError: The module could not be reached.
    """
    value: float | None
    if source.weather_sensor is not None:
        weather = await host.proxy(source.module, IWeather)
        reading = await weather.get_sensor_value(source.station or source.module, source.weather_sensor)
        value = reading.value
    else:
        readings = await (await host.proxy(source.module, ITemperatures)).get_temperatures()
        if source.sensor not in readings:
            known = ", ".join(sorted(readings)) or "none"
            raise ModuleError(f"{source.describe()}: no such sensor (it has: {known})")
        value = readings[source.sensor]
    if value is None or not math.isfinite(value):
        raise ModuleError(f"{source.describe()}: no reading now")
    return float(value)
