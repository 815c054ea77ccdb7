"""Roofs, domes and telescopes react to the weather by themselves; the dome follows the telescope."""

from __future__ import annotations

import asyncio

import pytest

from nightcrew.errors import AbortedError, DeviceBusyError, MoveError
from nightcrew.events import (
    BadWeatherEvent,
    GoodWeatherEvent,
    RoofClosedEvent,
    RoofClosingEvent,
    RoofOpenedEvent,
)
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.sim import SimDome, SimRoof, SimTelescope
from nightcrew.testing import EventRecorder, Observatory

BETELGEUSE = (88.7929, 7.4071)


async def test_roof_opens_and_closes_with_events(observatory: Observatory) -> None:
    recorder = await observatory.start(
        EventRecorder, "recorder", types=[RoofOpenedEvent, RoofClosingEvent, RoofClosedEvent]
    )
    roof = await observatory.start(SimRoof, "roof", open_time=30.0, close_time=20.0)
    start = observatory.clock.time()
    await roof.open_roof()
    # Never faster than open_time; later only by event-loop latency (5 clock s = 50 ms of wall).
    assert 29.9 <= observatory.clock.time() - start < 35.0
    assert (await roof.get_motion_status(), roof.opened) == (MotionStatus.IDLE, 1.0)
    await roof.close_roof()
    assert await roof.get_motion_status() is MotionStatus.PARKED
    await observatory.clock.sleep(0.5)
    assert [type(e) for e, _ in recorder.events] == [RoofOpenedEvent, RoofClosingEvent, RoofClosedEvent]


async def test_roof_refuses_a_second_opening_and_closing_aborts_an_opening(observatory: Observatory) -> None:
    roof = await observatory.start(SimRoof, "roof", open_time=60.0)
    opening = asyncio.create_task(roof.open_roof())
    await observatory.clock.sleep(15.0)
    with pytest.raises(DeviceBusyError, match=r"busy \(opening\)"):
        await roof.open_roof()
    await roof.close_roof()
    with pytest.raises(AbortedError, match=r"opening was aborted \(pre-empted by closing\)"):
        await opening
    assert roof.opened == 0.0 and await roof.get_motion_status() is MotionStatus.PARKED


async def test_bad_weather_closes_the_roof_and_parks_the_telescope_by_themselves(
    observatory: Observatory,
) -> None:
    weather = await observatory.start(EventRecorder, "weather", types=[])
    roof = await observatory.start(SimRoof, "roof", open_time=40.0, close_time=40.0)
    telescope = await observatory.start(SimTelescope, "telescope")
    await roof.open_roof()
    await telescope.init()
    await telescope.move_radec(*BETELGEUSE)
    await weather.comm.send_event(BadWeatherEvent(reason="rain"))

    def safe() -> bool:
        return roof._motion_status is MotionStatus.PARKED and telescope._motion_status is MotionStatus.PARKED

    await observatory.wait_for(safe, 60.0, interval=0.5)
    with pytest.raises(MoveError, match=r"weather is bad \(rain\); the roof stays closed until it is good"):
        await roof.open_roof()
    assert roof.opened == 0.0
    await weather.comm.send_event(GoodWeatherEvent())
    await observatory.clock.sleep(1.0)
    await roof.open_roof()
    assert roof.opened == 1.0


async def test_bad_weather_while_the_roof_opens_closes_it(observatory: Observatory) -> None:
    weather = await observatory.start(EventRecorder, "weather", types=[])
    roof = await observatory.start(SimRoof, "roof", open_time=40.0, close_time=40.0)
    opening = asyncio.create_task(roof.open_roof())
    await observatory.clock.sleep(20.0)
    await weather.comm.send_event(BadWeatherEvent(reason="wind"))
    with pytest.raises(AbortedError):
        await opening
    await observatory.wait_for(lambda: roof._motion_status is MotionStatus.PARKED, 60.0, interval=0.5)
    assert roof.opened == 0.0


async def test_dome_follows_the_telescope(observatory: Observatory) -> None:
    telescope = await observatory.start(SimTelescope, "telescope")
    dome = await observatory.start(
        SimDome, "dome", follow="telescope", follow_interval=2.0, follow_tolerance=1.0, rotation_speed=10.0
    )
    await telescope.init()
    await telescope.move_altaz(40.0, 200.0)

    async def lag() -> float:
        return abs((await dome.get_azimuth() - 200.0 + 180.0) % 360.0 - 180.0)

    start = observatory.clock.time()
    while await lag() > 1.0:
        assert observatory.clock.time() - start < 60.0, "dome did not follow"
        await observatory.clock.sleep(1.0)
    cards = await dome.get_fits_header_before()
    assert cards["DOME-AZ"][0] == pytest.approx(200.0, abs=1.0)
    assert await dome.get_motion_status() is MotionStatus.PARKED  # the shutter stays closed
