"""Focusers, filter wheels, weather stations and spectrographs: refusals, events, headers, sim truth."""

from __future__ import annotations

import asyncio

import pytest

from nightcrew.errors import ConfigError, DeviceBusyError, InvalidArgumentError, MoveError, RemoteTimeoutError
from nightcrew.events import FilterChangedEvent, NewSpectrumEvent
from nightcrew.interfaces import IFocuser, ITemperatures, MotionStatus, WeatherSensor
from nightcrew.modules import Module
from nightcrew.modules.sim import ISimFocuserTruth, SimFilterWheel, SimFocuser, SimWeatherStation
from nightcrew.testing import EventRecorder, Observatory

from .devices import BrokenFocuser, LineSpectrograph

FILTERS = ["B", "V", "R", "clear"]


async def test_unknown_filter_is_refused_listing_the_known_ones(observatory: Observatory) -> None:
    wheel = await observatory.start(SimFilterWheel, "filters", filters=FILTERS, filter_name="V")
    with pytest.raises(
        InvalidArgumentError, match=r"unknown filter 'H-alpha'; known filters: B, V, R, clear"
    ):
        await wheel.set_filter("H-alpha")
    assert await wheel.get_filter() == "V"
    assert await wheel.get_motion_status() is MotionStatus.IDLE


async def test_filter_change_takes_time_sends_an_event_and_fills_the_header(observatory: Observatory) -> None:
    recorder = await observatory.start(EventRecorder, "recorder", types=[FilterChangedEvent])
    wheel = await observatory.start(SimFilterWheel, "filters", filters=FILTERS, change_time=4.0)
    assert await wheel.list_filters() == FILTERS and await wheel.get_filter() == "B"
    change = asyncio.create_task(wheel.set_filter("R"))
    await observatory.clock.sleep(1.0)
    with pytest.raises(DeviceBusyError, match="moving to filter R"):
        await wheel.set_filter("V")
    await change
    await observatory.clock.sleep(0.5)
    assert recorder.of(FilterChangedEvent) == [FilterChangedEvent(filter_name="R")]
    assert await wheel.get_fits_header_before() == {"FILTER": ("R", "Filter in the beam")}


def test_filter_wheel_config_is_checked() -> None:
    with pytest.raises(ConfigError, match="key 'filters': filter names must be unique, got V, V"):
        SimFilterWheel(name="f", filters=["V", "V"])
    with pytest.raises(ConfigError, match="key 'filter_name': unknown filter 'U'; known filters: V"):
        SimFilterWheel(name="f", filters=["V"], filter_name="U")


async def test_focus_outside_the_range_is_refused_and_the_focus_stays(observatory: Observatory) -> None:
    focuser = await observatory.start(SimFocuser, "focuser", min_focus=10.0, max_focus=40.0, speed=5.0)
    await focuser.set_focus(30.0)
    with pytest.raises(InvalidArgumentError, match=r"= 45.0000 mm is outside the focuser range 10..40 mm"):
        await focuser.set_focus(45.0)
    with pytest.raises(
        InvalidArgumentError, match=r"focus 30.0000 mm \+ offset 12.0000 mm = 42.0000 mm is outside"
    ):
        await focuser.set_focus_offset(12.0)
    assert (await focuser.get_focus(), await focuser.get_focus_offset()) == (30.0, 0.0)
    await focuser.set_focus_offset(-1.5)
    assert await focuser.get_fits_header_before() == {
        "FOCUS": (28.5, "Focuser position [mm]"),
        "FOCOFFS": (-1.5, "Focus offset included in FOCUS [mm]"),
    }


async def test_a_failing_motor_is_a_move_error_and_an_error_status(observatory: Observatory) -> None:
    focuser = await observatory.start(BrokenFocuser, "focuser", focus=20.0)
    with pytest.raises(
        MoveError, match=r"focuser failed to move to 21\.0000 mm: OSError: motor driver not responding"
    ):
        await focuser.set_focus(21.0)
    assert await focuser.get_focus() == 20.0
    assert await focuser.get_motion_status() is MotionStatus.ERROR


async def test_best_focus_follows_the_weather_stations_temperature(observatory: Observatory) -> None:
    scenario = [{"at": 0, "temperature": 10.0}, {"at": 3600, "temperature": 0.0}]
    await observatory.start(SimWeatherStation, "weather", scenario=scenario, interval=10.0)
    focuser = await observatory.start(
        SimFocuser, "focuser", best_focus=25.0, temperature_coefficient=-0.05, weather_station="weather"
    )
    truth = await focuser.comm.proxy("focuser", ISimFocuserTruth)
    assert await truth.get_best_focus() == pytest.approx(25.0, abs=0.01)
    start = observatory.clock.time()
    await observatory.clock.sleep(120.0)
    ambient = (await (await focuser.comm.proxy("weather", ITemperatures)).get_temperatures())["ambient"]
    assert ambient < 10.0 - 100.0 / 360.0  # cooled by at least 100 s worth of the 10 °C/h drop
    assert observatory.clock.time() - start < 200.0
    assert await truth.get_best_focus() == pytest.approx(25.0 - 0.05 * (ambient - 10.0))


async def test_weather_station_reports_its_scenario_and_refuses_other_stations(
    observatory: Observatory,
) -> None:
    scenario = [{"at": 0, "temperature": 5.0, "humidity": 40.0, "clouds": 0.0}, {"at": 20, "rain": True}]
    station = await observatory.start(SimWeatherStation, "weather", scenario=scenario, interval=5.0)
    assert await station.is_weather_good()
    value = await station.get_sensor_value("weather", WeatherSensor.TEMPERATURE)
    assert value.value == 5.0
    assert (await station.get_sensor_value("", WeatherSensor.SKY_TEMPERATURE)).value == -25.0
    assert await station.get_temperatures() == {"ambient": 5.0}
    with pytest.raises(InvalidArgumentError, match="this is weather station 'weather', not 'roof'"):
        await station.get_sensor_value("roof", WeatherSensor.TEMPERATURE)
    with pytest.raises(InvalidArgumentError, match="has no particles sensor; it has: temperature, humidity"):
        await station.get_sensor_value("weather", WeatherSensor.PARTICLES)
    await observatory.clock.sleep(30.0)
    report = await station.get_current_weather()
    assert report.good is False and report.sensors["rain"] == 1.0


def test_weather_scenario_errors_name_the_entry() -> None:
    with pytest.raises(ConfigError, match=r"key 'scenario': entry 1: unknown keys \['snow'\]"):
        SimWeatherStation(name="w", scenario=[{"at": 0}, {"at": 10, "snow": 1}])
    with pytest.raises(ConfigError, match=r"entry 0: humidity must be within 0..100 %, got 120"):
        SimWeatherStation(name="w", scenario=[{"at": 0, "humidity": 120}])


async def test_spectrograph_writes_a_spectrum_and_announces_it(observatory: Observatory) -> None:
    recorder = await observatory.start(EventRecorder, "recorder", types=[NewSpectrumEvent])
    spectrograph = await observatory.start(LineSpectrograph, "spectrograph")
    with pytest.raises(InvalidArgumentError, match=r"exposure_time -5\.0 s is out of range"):
        await spectrograph.set_exposure_time(-5.0)
    await spectrograph.set_exposure_time(10.0)
    grab = asyncio.create_task(spectrograph.grab_spectrum())
    await observatory.clock.sleep(2.0)
    with pytest.raises(DeviceBusyError):
        await spectrograph.grab_spectrum()
    filename = await grab
    assert filename.endswith("-spectrum.fits")
    hdu = (await observatory.vfs.read_fits(filename))[0]
    assert hdu.data.shape == (256,) and hdu.header["GRATING"] == "600/mm" and hdu.header["EXPTIME"] == 10.0
    await observatory.clock.sleep(0.5)
    assert recorder.of(NewSpectrumEvent) == [NewSpectrumEvent(filename=filename)]


class _StuckFocuser(SimFocuser):
    """A focuser whose moves never end."""

    async def _hw_move_focus(self, position: float) -> None:
        await self.clock.sleep(1e9)


async def test_a_stuck_focuser_is_noticed_after_its_travel_at_its_speed(observatory: Observatory) -> None:
    await observatory.start(_StuckFocuser, "focuser", min_focus=0.0, max_focus=50.0, focus=25.0, speed=0.5)
    caller = await observatory.start(Module, "caller")
    remote = await caller.comm.proxy("focuser", IFocuser)
    started = observatory.clock.time()
    # 10 mm at 0.5 mm/s: 20 s, announced with 30 s of margin and 10 wall seconds (clock speed 1)
    # - not the interface's 300 s.
    with pytest.raises(RemoteTimeoutError, match=r"set_focus\(\) did not finish within 60 s"):
        await remote.set_focus(35.0)
    assert 60 <= observatory.clock.time() - started < 70
