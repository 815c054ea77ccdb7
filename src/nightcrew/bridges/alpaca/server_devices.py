"""The weather verdict and sensors served as Alpaca devices.

* SafetyMonitor: IsSafe is the weather module's verdict (IWeather.is_weather_good).
* ObservingConditions: the sensors an IWeather module reports (wind speed in m/s, as Alpaca has it).
"""

from __future__ import annotations

from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest
from nightcrew.errors import InvalidArgumentError, NightcrewError, NotSupportedError
from nightcrew.interfaces import (
    IWeather,
    WeatherSensor,
)

__all__ = [
    "ServedObservingConditions",
    "ServedSafetyMonitor",
]


class ServedSafetyMonitor(ServedDevice):
    """Alpaca SafetyMonitor on the weather module's verdict."""

    device_type = "safetymonitor"
    type_name = "SafetyMonitor"
    interface_version = 3  # ISafetyMonitorV3 (Platform 7)
    state_members = ("IsSafe",)
    interface = IWeather

    async def get_issafe(self, request: AlpacaRequest) -> bool:
        return await (await self.proxy(IWeather)).is_weather_good()


#: ObservingConditions member → (nightcrew sensor, factor to Alpaca's unit).
_CONDITIONS = {
    "temperature": (WeatherSensor.TEMPERATURE, 1.0),
    "humidity": (WeatherSensor.HUMIDITY, 1.0),
    "pressure": (WeatherSensor.PRESSURE, 1.0),
    "windspeed": (WeatherSensor.WIND_SPEED, 1.0 / 3.6),  # km/h -> m/s
    "winddirection": (WeatherSensor.WIND_DIRECTION, 1.0),
    "skytemperature": (WeatherSensor.SKY_TEMPERATURE, 1.0),
    "dewpoint": (WeatherSensor.DEW_POINT, 1.0),
    "skyquality": (WeatherSensor.SKY_BRIGHTNESS, 1.0),  # mag/arcsec²
}


class ServedObservingConditions(ServedDevice):
    """Alpaca ObservingConditions (IObservingConditionsV1) on the sensors an IWeather module reports
    (a weather station: all of its sensors; the weather module: those it checks). Sensors it does
    not report (cloud cover, rain rate, star FWHM, ...) answer NotImplemented."""

    device_type = "observingconditions"
    type_name = "ObservingConditions"
    interface_version = 2  # IObservingConditionsV2 (Platform 7)
    state_members = (
        "CloudCover",
        "DewPoint",
        "Humidity",
        "Pressure",
        "RainRate",
        "SkyBrightness",
        "SkyQuality",
        "SkyTemperature",
        "StarFWHM",
        "Temperature",
        "WindDirection",
        "WindGust",
        "WindSpeed",
    )
    interface = IWeather

    async def _sensor(self, member: str) -> float:
        sensor, factor = _CONDITIONS[member]
        report = await (await self.proxy(IWeather)).get_current_weather()
        if sensor.value not in report.sensors:
            raise NotSupportedError(f"{member}: module {self.module} reports no {sensor.value}")
        value = report.sensors[sensor.value]
        if value is None:
            raise NightcrewError(f"{member}: module {self.module} has no {sensor.value} reading now")
        return value * factor

    async def get_temperature(self, request: AlpacaRequest) -> float:
        return await self._sensor("temperature")

    async def get_humidity(self, request: AlpacaRequest) -> float:
        return await self._sensor("humidity")

    async def get_pressure(self, request: AlpacaRequest) -> float:
        return await self._sensor("pressure")

    async def get_windspeed(self, request: AlpacaRequest) -> float:
        return await self._sensor("windspeed")

    async def get_winddirection(self, request: AlpacaRequest) -> float:
        return await self._sensor("winddirection")

    async def get_skytemperature(self, request: AlpacaRequest) -> float:
        return await self._sensor("skytemperature")

    async def get_dewpoint(self, request: AlpacaRequest) -> float:
        return await self._sensor("dewpoint")

    async def get_skyquality(self, request: AlpacaRequest) -> float:
        return await self._sensor("skyquality")

    async def get_averageperiod(self, request: AlpacaRequest) -> float:
        return 0.0  # readings are passed on as they come

    async def put_averageperiod(self, request: AlpacaRequest) -> None:
        period = request.number("AveragePeriod")
        if period != 0.0:
            raise InvalidArgumentError(f"averageperiod must be 0 (readings are not averaged), got {period}")

    async def get_sensordescription(self, request: AlpacaRequest) -> str:
        member = request.string("SensorName").lower()
        if member not in _CONDITIONS:
            raise NotSupportedError(f"sensordescription: no sensor {member!r} here")
        await self._sensor(member)  # reported at all?
        return f"{_CONDITIONS[member][0].value} of nightcrew module {self.module}"

    async def get_timesincelastupdate(self, request: AlpacaRequest) -> float:
        member = request.string("SensorName").lower()
        if member and member not in _CONDITIONS:
            raise NotSupportedError(f"timesincelastupdate: no sensor {member!r} here")
        report = await (await self.proxy(IWeather)).get_current_weather()
        return max(0.0, self.owner.clock.time() - report.time.timestamp())
