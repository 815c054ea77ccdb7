"""A short observing sequence on INDI devices only: open the dome, slew, change filter, move the
focuser, take two exposures (FITS files with everybody's headers), park, close."""

from __future__ import annotations

import io

from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.astro import angular_separation
from nightcrew.clock import RealClock
from nightcrew.events import NewImageEvent, RoofClosedEvent, RoofOpenedEvent
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.indi import (
    IndiCamera,
    IndiDome,
    IndiFilterWheel,
    IndiFocuser,
    IndiRotator,
    IndiTelescope,
    IndiWeather,
)
from nightcrew.modules.weather import ModuleStation, Weather
from nightcrew.testing import EventRecorder, Observatory, wait_for
from nightcrew.testing.indi import IndiServer
from nightcrew.weather import Boolean


async def test_a_short_sequence_on_indi_devices_only(indi_server: IndiServer) -> None:
    at = {"host": indi_server.host, "port": indi_server.port}
    async with Observatory(clock=RealClock()) as obs:
        recorder = await obs.start(
            EventRecorder, "recorder", types=[NewImageEvent, RoofOpenedEvent, RoofClosedEvent]
        )
        await obs.start(IndiWeather, "indiweather", device="Weather Simulator", interval=1.0, **at)
        weather = await obs.start(
            Weather,
            "weather",
            stations={"indi": ModuleStation(module="indiweather")},
            checks={"indi.safe": Boolean(good_when=True)},
            interval=1.0,
            min_good_time=0.0,
        )
        # Fail safe, the weather is bad until the INDI station's first reading: wait for good
        # weather before the devices start, or they would park and close at once.
        await wait_for(weather.is_weather_good, 30, message="good weather")
        telescope = await obs.start(IndiTelescope, "telescope", device="Telescope Simulator", **at)
        dome = await obs.start(
            IndiDome, "dome", device="Dome Simulator", follow="telescope", follow_interval=1.0, **at
        )
        wheel = await obs.start(IndiFilterWheel, "filters", device="Filter Simulator", **at)
        focuser = await obs.start(IndiFocuser, "focuser", device="Focuser Simulator", max_focus=100.0, **at)
        await obs.start(IndiRotator, "rotator", device="Rotator Simulator", **at)
        camera = await obs.start(
            IndiCamera,
            "camera",
            device="CCD Simulator",
            filename_pattern="/cache/seq-{FILTER}-{DATE-OBS}.fits",
            fits_headers={"OBSERVER": "nightcrew"},
            **at,
        )

        await dome.open_roof()
        await telescope.init()
        # Near the mount's park position (hour angle -6 h, Dec 0: east on the horizon), so that the
        # simulator's real-time slew and park are short; 15° from the dome's park azimuth (90°).
        ra, dec = telescope._radec_of(25.0, 105.0)
        await telescope.move_radec(ra, dec)
        names = await wheel.list_filters()
        await wheel.set_filter(names[2] if await wheel.get_filter() != names[2] else names[3])
        await focuser.set_focus(42.0)
        # The dome follows the telescope by itself.
        _, az = await telescope.get_altaz()
        await wait_for(
            lambda: (
                abs(
                    (dome._indi.vector("ABS_DOME_POSITION").number("DOME_ABSOLUTE_POSITION") - az + 180) % 360
                    - 180
                )
                < 3.0
            ),
            60,
            message="the dome at the telescope's azimuth",
        )
        await camera.set_exposure_time(0.5)
        paths = [await camera.grab_data(), await camera.grab_data()]
        await telescope.park()
        await dome.close_roof()

        assert await telescope.get_motion_status() is MotionStatus.PARKED
        assert await dome.get_motion_status() is MotionStatus.PARKED
        assert len(recorder.of(RoofOpenedEvent)) == 1 and len(recorder.of(RoofClosedEvent)) == 1
        assert [e.filename for e in recorder.of(NewImageEvent)] == paths and len(set(paths)) == 2
        for path in paths:
            with fits.open(io.BytesIO(await obs.vfs.read_bytes(path))) as hdus:
                header, data = hdus[0].header, hdus[0].data
            assert data.shape == (1024, 1280)
            assert header["FILTER"] == await wheel.get_filter()
            assert header["FOCUS"] == 42.0
            assert angular_separation(header["RA"], header["DEC"], ra, dec) < 1.0 / 60.0
            assert "OBJCTRA" in header and "AIRMASS" in header and "DOME-AZ" in header
            assert "ROTPA" in header and header["WS-GOOD"] is not None
            assert header["OBSERVER"] == "nightcrew" and header["EXPTIME"] == 0.5
            assert "CCD-TEMP" in header and "DATE-OBS" in header and "SITELAT" in header
