"""Domes and roofs, and the weather verdict served as Alpaca devices.

* Dome: any IRoof module (a roll-off roof or a dome's shutter); an IDome also has an azimuth.
* SafetyMonitor: IsSafe is the weather module's verdict (IWeather.is_weather_good).
* ObservingConditions: the sensors an IWeather module reports (wind speed in m/s, as Alpaca has it).
"""

from __future__ import annotations

from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest
from nightcrew.errors import InvalidArgumentError, NightcrewError, NotSupportedError
from nightcrew.interfaces import (
    IDome,
    IRoof,
    IWeather,
    MotionStatus,
    WeatherSensor,
)

__all__ = [
    "ServedDome",
    "ServedObservingConditions",
    "ServedSafetyMonitor",
]

#: ShutterState.
_OPEN, _CLOSED, _OPENING, _CLOSING, _ERROR = range(5)
_SHUTTER = {
    MotionStatus.IDLE: _OPEN,
    MotionStatus.PARKED: _CLOSED,
    MotionStatus.MOVING: _OPENING,
    MotionStatus.INITIALIZING: _OPENING,
    MotionStatus.PARKING: _CLOSING,
}


class ServedDome(ServedDevice):
    """Alpaca Dome (IDomeV3 members) on a nightcrew IRoof module; IDome adds the azimuth."""

    device_type = "dome"
    type_name = "Dome"
    interface_version = 3  # IDomeV3 (Platform 7)
    state_members = ("Altitude", "AtHome", "AtPark", "Azimuth", "ShutterStatus", "Slewing")
    interface = IRoof

    async def _roof(self) -> IRoof:
        return await self.proxy(IRoof)

    async def _dome(self, member: str) -> IDome:
        dome = await self.optional(IDome)
        if dome is None:
            raise NotSupportedError(f"{member}: module {self.module} is a roof without azimuth")
        return dome

    async def get_shutterstatus(self, request: AlpacaRequest) -> int:
        self.action.raise_failure()
        return _SHUTTER.get(await (await self._roof()).get_motion_status(), _ERROR)

    async def put_openshutter(self, request: AlpacaRequest) -> None:
        roof = await self._roof()
        self.action.start("openshutter", roof.open_roof)
        await self.action.settle(self.settle_time)

    async def put_closeshutter(self, request: AlpacaRequest) -> None:
        roof = await self._roof()
        self.action.start("closeshutter", roof.close_roof, preempt=True)  # closing always wins
        await self.action.settle(self.settle_time)

    async def put_abortslew(self, request: AlpacaRequest) -> None:
        roof = await self._roof()
        await roof.stop_motion()
        await self.action.cancel()

    async def get_cansetshutter(self, request: AlpacaRequest) -> bool:
        return True

    async def get_cansetazimuth(self, request: AlpacaRequest) -> bool:
        return await self.optional(IDome) is not None

    async def get_canfindhome(self, request: AlpacaRequest) -> bool:
        return False

    get_canpark = get_cansetpark = get_cansetaltitude = get_cansyncazimuth = get_canslave = get_canfindhome
    get_athome = get_atpark = get_slaved = get_canfindhome

    async def put_slaved(self, request: AlpacaRequest) -> None:
        if request.boolean("Slaved"):
            raise NotSupportedError("slaved: nightcrew domes follow the telescope by their own configuration")

    async def get_slewing(self, request: AlpacaRequest) -> bool:
        self.action.raise_failure()
        return self.action.current == "slewtoazimuth"

    async def get_azimuth(self, request: AlpacaRequest) -> float:
        return await (await self._dome("azimuth")).get_azimuth()

    async def put_slewtoazimuth(self, request: AlpacaRequest) -> None:
        azimuth = request.number("Azimuth")
        if not 0.0 <= azimuth < 360.0:
            raise InvalidArgumentError(f"azimuth must be within 0..360 degrees, got {azimuth}")
        dome = await self._dome("slewtoazimuth")
        self.action.start("slewtoazimuth", lambda: dome.move_azimuth(azimuth))
        await self.action.settle(self.settle_time)


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
