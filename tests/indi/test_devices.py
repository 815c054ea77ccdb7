"""What the contract suites do not cover: rotator and weather station, the camera's data path,
the telescope's J2000 handling, sync and tracking, and motions started by another INDI client."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.astro import angular_separation, j2000_to_of_date
from nightcrew.bridges.indi import IndiClient
from nightcrew.clock import RealClock
from nightcrew.errors import InvalidArgumentError
from nightcrew.events import BadWeatherEvent, GoodWeatherEvent, MotionStatusChangedEvent
from nightcrew.interfaces import ImageType, ISyncRaDec, ModuleState, MotionStatus, PierSide, WeatherSensor
from nightcrew.interfaces.quantities import MAX_EXPOSURE_TIME
from nightcrew.modules import Module
from nightcrew.modules.indi import IndiCamera, IndiFocuser, IndiRotator, IndiTelescope, IndiWeather
from nightcrew.modules.weather import ModuleStation, Weather
from nightcrew.testing import EventRecorder, Observatory, wait_for
from nightcrew.testing.indi import IndiServer
from nightcrew.weather import Boolean


def _at(server: IndiServer, device: str) -> dict[str, Any]:
    return {"host": server.host, "port": server.port, "device": device}


async def _raw_client(server: IndiServer, device: str) -> IndiClient:
    """Another INDI client of the same server (as KStars would be)."""
    client = IndiClient(server.host, server.port, devices=[device])
    await client.open()
    await client.wait_connected(within=10)
    await client.wait_defined(device, "CONNECTION", 10)
    return client


async def test_rotator_turns_reverses_and_reports(indi_server: IndiServer) -> None:
    async with Observatory(clock=RealClock()) as obs:
        rotator = await obs.start(IndiRotator, "rotator", **_at(indi_server, "Rotator Simulator"))
        await rotator.move_position_angle(30.0)
        assert await rotator.get_position_angle() == pytest.approx(30.0, abs=0.01)
        await rotator.move_position_angle_by(-40.0)
        assert await rotator.get_position_angle() == pytest.approx(350.0, abs=0.01)
        assert await rotator.get_motion_status() is MotionStatus.IDLE
        await rotator.set_rotator_reversed(True)
        assert await rotator.get_rotator_reversed() is True
        await rotator.set_rotator_reversed(False)
        cards = await rotator.get_fits_header_before()
        assert cards["ROTPA"][0] == pytest.approx(350.0, abs=0.01)


async def test_weather_parameters_are_sensors_and_the_indi_state_is_an_evaluator_input(
    indi_server: IndiServer,
) -> None:
    control = await _raw_client(indi_server, "Weather Simulator")
    async with Observatory(clock=RealClock()) as obs:
        recorder = await obs.start(EventRecorder, "recorder", types=[BadWeatherEvent, GoodWeatherEvent])
        station = await obs.start(
            IndiWeather, "indiweather", interval=0.5, **_at(indi_server, "Weather Simulator")
        )
        weather = await obs.start(
            Weather,
            "weather",
            stations={"indi": ModuleStation(module="indiweather")},
            checks={"indi.safe": Boolean(good_when=True), "indi.rain": Boolean(good_when=False)},
            interval=0.5,
            min_good_time=0.0,
        )
        try:
            await control.wait_defined("Weather Simulator", "WEATHER_CONTROL", 10)
            await control.send(
                "Weather Simulator", "WEATHER_CONTROL", {"Precip": 0.0, "Temperature": 12.5}, wait=10
            )
            await control.send("Weather Simulator", "WEATHER_REFRESH", {"REFRESH": True}, wait=10)
            await wait_for(weather.is_weather_good, 30, message="good weather")
            # The station reads at once on connection, maybe before the new temperature: wait for it.
            await wait_for(
                lambda: station._value(WeatherSensor.TEMPERATURE) == pytest.approx(12.5),
                30,
                message="12.5 °C",
            )
            report = await station.get_current_weather()
            assert report.sensors["temperature"] == pytest.approx(12.5) and report.sensors["safe"] == 1.0
            # Rain: the driver's state goes to Alert, the Weather module closes the observatory.
            recorder.clear()
            await control.send("Weather Simulator", "WEATHER_CONTROL", {"Precip": 10.0}, wait=10)
            await control.send("Weather Simulator", "WEATHER_REFRESH", {"REFRESH": True}, wait=10)
            await wait_for(lambda: bool(recorder.of(BadWeatherEvent)), 30, message="BadWeatherEvent")
            await wait_for(lambda: station._value(WeatherSensor.SAFE) == 0.0, 30, message="unsafe")
            assert not await station.is_weather_good()
            assert (await station.get_current_weather()).sensors == pytest.approx(
                {**report.sensors, "rain": 1.0, "safe": 0.0}
            )
            assert "indi.safe" in recorder.of(BadWeatherEvent)[-1].reason
        finally:
            await control.send(
                "Weather Simulator", "WEATHER_CONTROL", {"Precip": 0.0, "Temperature": 15.0}, wait=10
            )
            await control.send("Weather Simulator", "WEATHER_REFRESH", {"REFRESH": True}, wait=10)
            await control.close()


async def test_camera_refuses_exposures_beyond_the_drivers_maximum(indi_server: IndiServer) -> None:
    async with Observatory(clock=RealClock()) as obs:
        camera = await obs.start(
            IndiCamera, "camera", max_exposure_time=MAX_EXPOSURE_TIME, **_at(indi_server, "CCD Simulator")
        )
        high = camera._indi.vector("CCD_EXPOSURE").limits["CCD_EXPOSURE_VALUE"][1]
        assert 0 < high < MAX_EXPOSURE_TIME
        await camera.set_exposure_time(high)
        with pytest.raises(
            InvalidArgumentError, match=r"out of range for camera: .*\(the maximum is the device's"
        ):
            await camera.set_exposure_time(high + 1)
        assert await camera.get_exposure_time() == high


@pytest.mark.parametrize("compress", [False, True])
async def test_camera_data_path_size_type_headers_compression(
    indi_server: IndiServer, compress: bool
) -> None:
    async with Observatory(clock=RealClock()) as obs:
        camera = await obs.start(
            IndiCamera,
            "camera",
            compress=compress,
            gain=55.0,
            fits_headers={"TELESCOP": "nightcrew test"},
            **_at(indi_server, "CCD Simulator"),
        )
        full = await camera.get_full_frame()
        assert (full.width, full.height) == (1280, 1024)
        await camera.set_binning(2, 2)
        await camera.set_window(100, 200, 640, 400)
        await camera.set_exposure_time(0.2)
        path = await camera.grab_data(image_type=ImageType.DARK)
        with fits.open(io_bytes(await obs.vfs.read_bytes(path))) as hdus:
            data, header = hdus[0].data, hdus[0].header
        assert (data.shape == (200, 320) and data.dtype == np.dtype(">u2")) or data.dtype == np.uint16
        assert header["IMAGETYP"] == "dark" and header["EXPTIME"] == 0.2
        assert (header["XBINNING"], header["XORGSUBF"], header["YORGSUBF"]) == (2, 100, 200)
        assert header["TELESCOP"] == "nightcrew test" and header["ORIGIN"] == "nightcrew"
        assert header["GAIN"] == pytest.approx(55.0) and "CCD-TEMP" in header and "PIXSIZE1" in header
        assert "DATE-OBS" in header and "SITELAT" in header
        ccd = camera._indi.vector("CCD_COMPRESSION")
        assert ccd.members["INDI_ENABLED"] is compress


def io_bytes(data: bytes) -> Any:
    import io

    return io.BytesIO(data)


async def test_telescope_speaks_jnow_to_indi_and_j2000_to_nightcrew(indi_server: IndiServer) -> None:
    async with Observatory(clock=RealClock()) as obs:
        telescope = await obs.start(IndiTelescope, "telescope", **_at(indi_server, "Telescope Simulator"))
        await telescope.init()
        # Near the park position (hour angle -6 h, Dec 0): the simulator slews in real time.
        ra, dec = telescope._radec_of(25.0, 105.0)
        await telescope.move_radec(ra, dec)
        eod = telescope._indi.vector("EQUATORIAL_EOD_COORD")
        expected = j2000_to_of_date(ra, dec, obs.clock.time())
        assert angular_separation(eod.number("RA") * 15.0, eod.number("DEC"), *expected) < 1.0 / 60.0
        # Precession since 2000 is ~0.36 degrees: JNow differs from J2000 by more than the tolerance.
        assert angular_separation(eod.number("RA") * 15.0, eod.number("DEC"), ra, dec) > 0.2
        assert angular_separation(*await telescope.get_radec(), ra, dec) < 1.0 / 60.0
        assert await telescope.get_motion_status() is MotionStatus.TRACKING
        # East of the meridian the tube is on the west side of the pier (TELESCOPE_PIER_SIDE, ASCOM's sense).
        assert await telescope.get_pier_side() is PierSide.WEST
        assert (await telescope.get_fits_header_before())["PIERSIDE"][0] == "WEST"
        assert await telescope.get_destination_pier_side(ra, dec) is PierSide.UNKNOWN
        # Sync, called as any module would (ISyncRaDec over the comm, as docs/indi.md promises): the
        # mount now believes it points 0.5 degrees further north.
        caller = await obs.start(Module, "caller")
        await (await caller.proxy("telescope", ISyncRaDec)).sync_radec(ra, dec + 0.5)
        assert angular_separation(*await telescope.get_radec(), ra, dec + 0.5) < 1.0 / 60.0
        await telescope.set_tracking(False)
        assert await telescope.get_motion_status() is MotionStatus.IDLE
        assert not telescope._tracking()
        await telescope.park()
        assert await telescope.get_motion_status() is MotionStatus.PARKED


async def test_motions_by_another_client_are_reported(indi_server: IndiServer) -> None:
    """KStars (here: a second client) slews the mount and moves the focuser: nightcrew follows."""
    other = await _raw_client(indi_server, "Telescope Simulator")
    focus_other = await _raw_client(indi_server, "Focuser Simulator")
    async with Observatory(clock=RealClock()) as obs:
        recorder = await obs.start(EventRecorder, "recorder", types=[MotionStatusChangedEvent])
        telescope = await obs.start(IndiTelescope, "telescope", **_at(indi_server, "Telescope Simulator"))
        focuser = await obs.start(
            IndiFocuser, "focuser", max_focus=100.0, **_at(indi_server, "Focuser Simulator")
        )
        await telescope.init()
        await telescope.move_altaz(25.0, 95.0)  # short real-time slews, near the park position
        recorder.clear()
        ra, dec = telescope._radec_of(35.0, 115.0)
        ra_now, dec_now = j2000_to_of_date(ra, dec, obs.clock.time())
        try:
            await other.send(
                "Telescope Simulator", "ON_COORD_SET", {"TRACK": True, "SLEW": False, "SYNC": False}, wait=10
            )
            await other.send(
                "Telescope Simulator", "EQUATORIAL_EOD_COORD", {"RA": ra_now / 15, "DEC": dec_now}, wait=120
            )
            target = 30.0 if abs(await focuser.get_focus() - 30.0) > 5 else 60.0
            await focus_other.send(
                "Focuser Simulator", "ABS_FOCUS_POSITION", {"FOCUS_ABSOLUTE_POSITION": target * 1000}, wait=30
            )
        finally:
            await other.close()
            await focus_other.close()
        await wait_for(
            lambda: (
                [e.status for e in recorder.of(MotionStatusChangedEvent, sender="telescope")][-1:]
                == [MotionStatus.TRACKING]
            ),
            10,
            message="TRACKING after the other client's slew",
        )
        statuses = [e.status for e in recorder.of(MotionStatusChangedEvent, sender="telescope")]
        assert statuses[0] is MotionStatus.SLEWING
        assert angular_separation(*await telescope.get_radec(), ra, dec) < 0.1
        await wait_for(lambda: abs(focuser._focus - target) < 1e-6, 10, message="the new focus")
        assert await focuser.get_fits_header_before() == {
            "FOCUS": (target, "Focuser position [mm]"),
            "FOCOFFS": (0.0, "Focus offset included in FOCUS [mm]"),
        }
        assert focuser.state is ModuleState.READY and telescope.state is ModuleState.READY
