"""The Weather module end to end: stations → checks → events → roof and telescope react."""

from __future__ import annotations

import asyncio
import json
from collections.abc import AsyncIterator
from typing import Any

import pytest
from aiohttp import web

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.events import BadWeatherEvent, GoodWeatherEvent
from nightcrew.interfaces import MotionStatus, WeatherSensor
from nightcrew.modules.sim import SimRoof, SimTelescope, SimWeatherStation
from nightcrew.modules.weather import (
    Average,
    CsvFileStation,
    Current,
    HttpJsonStation,
    ModuleStation,
    Station,
    SunStation,
    Weather,
)
from nightcrew.testing import EventRecorder, Observatory
from nightcrew.weather import Boolean, Schmitt, Switch, Valid

BETELGEUSE = (88.7929, 7.4071)
RAIN_AT, DRY_AT, MIN_GOOD = 300.0, 600.0, 120.0


async def test_rain_closes_the_roof_and_parks_the_telescope_within_a_minute(
    fast_observatory: Observatory,
) -> None:
    obs = fast_observatory
    recorder = await obs.start(EventRecorder, "recorder", types=[BadWeatherEvent, GoodWeatherEvent])
    station = await obs.start(
        SimWeatherStation,
        "weatherstation",
        interval=5.0,
        scenario=[{"at": 0, "humidity": 50}, {"at": RAIN_AT, "rain": True}, {"at": DRY_AT, "rain": False}],
    )
    roof = await obs.start(SimRoof, "roof", open_time=30.0, close_time=30.0)
    telescope = await obs.start(SimTelescope, "telescope")
    started = obs.clock.time()
    weather = await obs.start(
        Weather,
        "weather",
        stations={"roof": ModuleStation(module="weatherstation")},
        checks={"roof.rain": Boolean(good_when=False), "roof.humidity": Switch(bad_above=90)},
        interval=5.0,  # with the station's 5 s: rain is seen within 10 s
        min_good_time=MIN_GOOD,
    )
    # Good from the start, but declared so only after the minimum good time.
    assert not await weather.is_weather_good()
    await obs.wait_for(lambda: bool(recorder.of(GoodWeatherEvent)), 300.0, interval=1.0)
    assert obs.clock.time() - started >= MIN_GOOD
    assert await weather.is_weather_good()
    await roof.open_roof()
    await telescope.init()
    await telescope.move_radec(*BETELGEUSE)
    assert obs.clock.time() - started < RAIN_AT, "the test's timeline is too slow"

    await obs.wait_for(lambda: obs.clock.time() - station._started >= RAIN_AT, RAIN_AT, interval=1.0)
    rain_started = station._started + RAIN_AT  # the scenario's clock starts with the station

    def safe() -> bool:
        parked = MotionStatus.PARKED
        return roof._motion_status is parked and telescope._motion_status is parked

    await obs.wait_for(safe, 60.0, interval=1.0)
    took = obs.clock.time() - rain_started
    print(f"rain → roof closed and telescope parked in {took:.1f} simulated s")
    assert took < 60.0
    bad = recorder.of(BadWeatherEvent)
    assert len(bad) == 1 and "roof.rain: is true" in bad[0].reason
    assert not await weather.is_weather_good()

    # Dry again at 600 s: good weather is declared only after the minimum good time.
    await obs.wait_for(lambda: len(recorder.of(GoodWeatherEvent)) == 2, 600.0, interval=1.0)
    declared = obs.clock.time() - started
    assert DRY_AT + MIN_GOOD <= declared <= DRY_AT + MIN_GOOD + 60.0  # never early; late by polling only
    eta = recorder.of(GoodWeatherEvent)[-1].eta
    assert eta is not None and abs(eta.timestamp() - obs.clock.time()) < 15.0
    assert len(recorder.of(BadWeatherEvent)) == 1  # announced on change only
    await roof.open_roof()
    assert roof.opened == 1.0


async def test_report_sensor_values_and_fits_header(fast_observatory: Observatory) -> None:
    obs = fast_observatory
    await obs.start(SimWeatherStation, "weatherstation", interval=10.0, scenario=[{"at": 0, "humidity": 55}])
    weather = await obs.start(
        Weather,
        "weather",
        stations={"roof": ModuleStation(module="weatherstation"), "sun": SunStation()},
        checks={
            "roof.rain": Boolean(),
            "roof.humidity": Schmitt(bad_above=90, good_below=85),
            "sun.sun_altitude": Switch(bad_above=-6),
        },
        min_good_time=0,
    )
    await obs.wait_for(lambda: weather._gate.is_good, 60.0, interval=1.0)
    report = await weather.get_current_weather()
    assert report.good and report.sensors["humidity"] == 55.0 and report.sensors["rain"] == 0.0
    assert report.sensors["sun_altitude"] is not None and report.sensors["sun_altitude"] < -18.0  # 22 h UTC
    value = await weather.get_sensor_value("roof", WeatherSensor.HUMIDITY)
    assert value.value == 55.0
    with pytest.raises(InvalidArgumentError, match="no station 'nope'; known: roof, sun"):
        await weather.get_sensor_value("nope", WeatherSensor.HUMIDITY)
    cards = await weather.get_fits_header_before()
    assert cards["WS-GOOD"] == (True, "Weather declared good")
    sun = cards["WS-SUNAL"][0]
    assert cards["WS-HUMID"][0] == 55.0 and isinstance(sun, float) and sun < -18.0


async def test_a_silent_station_is_bad_weather(fast_observatory: Observatory) -> None:
    """No station online at all: bad from the first evaluation (fail safe)."""
    obs = fast_observatory
    recorder = await obs.start(EventRecorder, "recorder", types=[BadWeatherEvent, GoodWeatherEvent])
    weather = await obs.start(
        Weather,
        "weather",
        stations={"roof": ModuleStation(module="missing")},
        checks={"roof.rain": Boolean()},
        min_good_time=0,
        station_timeout=5.0,
    )
    await obs.wait_for(lambda: bool(recorder.of(BadWeatherEvent)), 30.0, interval=1.0)
    assert recorder.of(BadWeatherEvent)[0].reason == "roof.rain: no value"
    assert not await weather.is_weather_good()


async def test_a_station_module_that_starts_late_is_read_when_it_comes_online(
    fast_observatory: Observatory,
) -> None:
    """The weather module up first (as under ``nightcrew up``): its station is read again as soon as
    the station module comes online, not a whole ``interval`` later."""
    obs = fast_observatory
    recorder = await obs.start(EventRecorder, "recorder", types=[BadWeatherEvent, GoodWeatherEvent])
    await obs.start(
        Weather,
        "weather",
        stations={"roof": ModuleStation(module="weatherstation")},
        checks={"roof.rain": Boolean(good_when=False)},
        interval=600.0,
        min_good_time=0,
    )
    await obs.wait_for(lambda: bool(recorder.of(BadWeatherEvent)), 30.0, interval=1.0)
    started = obs.clock.time()
    await obs.start(SimWeatherStation, "weatherstation", interval=5.0)
    await obs.wait_for(lambda: bool(recorder.of(GoodWeatherEvent)), 600.0, interval=1.0)
    assert obs.clock.time() - started < 60.0


async def test_a_station_that_stops_answering_turns_stale_then_bad(fast_observatory: Observatory) -> None:
    obs = fast_observatory
    recorder = await obs.start(EventRecorder, "recorder", types=[BadWeatherEvent, GoodWeatherEvent])
    station = await obs.start(SimWeatherStation, "weatherstation", interval=10.0)
    await obs.start(
        Weather,
        "weather",
        stations={"roof": ModuleStation(module="weatherstation")},
        checks={"roof.rain": [Valid(max_age=120), Boolean()]},
        interval=10.0,
        min_good_time=0,
    )
    await obs.wait_for(lambda: bool(recorder.of(GoodWeatherEvent)), 30.0, interval=1.0)
    await station.close()
    gone = obs.clock.time()
    await obs.wait_for(lambda: bool(recorder.of(BadWeatherEvent)), 200.0, interval=1.0)
    assert 120.0 <= obs.clock.time() - gone <= 150.0
    assert "stale" in recorder.of(BadWeatherEvent)[0].reason


@pytest.fixture
async def json_station() -> AsyncIterator[tuple[str, dict[str, Any]]]:
    """A real HTTP server on 127.0.0.1 publishing a weather document that a test may change."""
    document: dict[str, Any] = {"current": {"temp": 4.0, "hum": 70, "rain": False}}

    async def handle(request: web.Request) -> web.Response:
        return web.Response(text=json.dumps(document), content_type="application/json")

    app = web.Application()
    app.router.add_get("/weather.json", handle)
    runner = web.AppRunner(app)
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    port = runner.addresses[0][1]
    try:
        yield f"http://127.0.0.1:{port}/weather.json", document
    finally:
        await runner.cleanup()


async def test_http_and_csv_stations_combined(
    fast_observatory: Observatory, json_station: tuple[str, dict[str, Any]], tmp_path: Any
) -> None:
    from nightcrew.vfs import LocalFile, VirtualFileSystem

    url, document = json_station
    obs = fast_observatory
    (tmp_path / "log.csv").write_text("time,T,humidity,rain\n2000-01-01T00:00:00,1,1,1\n")
    vfs = VirtualFileSystem({"weather": LocalFile(str(tmp_path))})
    now = obs.clock.now().isoformat()
    (tmp_path / "log.csv").write_text(f"time,T,humidity,rain\n2000-01-01T00:00:00,1,1,1\n{now},6.0,80,0\n")
    weather = await obs.start(
        Weather,
        "weather",
        vfs=vfs,
        stations={
            "web": HttpJsonStation(
                url=url,
                fields={"temperature": "/current/temp", "humidity": "/current/hum", "rain": "/current/rain"},
            ),
            "log": CsvFileStation(
                path="/weather/log.csv",
                columns={"temperature": "T", "humidity": "humidity", "rain": "rain"},
                time_column="time",
            ),
            "current": Current(stations=["web", "log"]),
            "mean": Average(stations=["web", "log"]),
        },
        checks={"current.rain": Boolean(), "mean.humidity": Switch(bad_above=90)},
        min_good_time=0,
    )
    await obs.wait_for(lambda: weather._gate.is_good, 30.0, interval=1.0)
    mean = await weather.get_sensor_value("mean", WeatherSensor.HUMIDITY)
    assert mean.value == pytest.approx(75.0)
    assert (await weather.get_sensor_value("log", WeatherSensor.TEMPERATURE)).value == 6.0
    assert (await weather.get_sensor_value("web", WeatherSensor.TEMPERATURE)).value == 4.0
    document["current"]["rain"] = True
    await obs.wait_for(lambda: not weather._gate.is_good, 60.0, interval=1.0)
    assert "current.rain: is true" in weather._bad_reason()
    await asyncio.sleep(0)


def test_config_errors_name_the_key() -> None:
    station: dict[str, Station] = {"roof": ModuleStation(module="ws")}
    with pytest.raises(ConfigError, match=r"not station\.sensor with a known station") as info:
        Weather(name="w", stations=station, checks={"nope.rain": Boolean()})
    assert info.value.key == "checks"
    with pytest.raises(ConfigError, match="'roof' is not a \\(non-combined\\) station") as info:
        Weather(name="w", stations={"a": Current(stations=["roof"])}, checks={"a.rain": Boolean()})
    assert info.value.key == "stations.a"
    with pytest.raises(ConfigError, match="needs the observatory's site") as info:
        Weather(name="w", stations={"sun": SunStation()}, checks={"sun.sun_altitude": Switch(bad_above=0)})
    assert info.value.key == "site"
    with pytest.raises(ConfigError, match="must be > 0") as info:
        Weather(name="w", stations=station, checks={"roof.rain": Boolean()}, interval=0)
    assert info.value.key == "interval"
