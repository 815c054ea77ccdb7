"""BaseRotator through SimRotator: moves take time, can be halted, refuse what they should."""

from __future__ import annotations

import asyncio
import math

import pytest

from nightcrew.errors import AbortedError, DeviceBusyError, InvalidArgumentError
from nightcrew.interfaces import IRotator, MotionStatus
from nightcrew.modules.sim import SimRotator
from nightcrew.testing import ContractProbe, ContractSetup, Observatory, timed_call


async def test_moves_take_the_short_way_at_the_set_speed(observatory: Observatory) -> None:
    rotator = await observatory.start(SimRotator, "rotator", speed=5.0)
    start = observatory.clock.time()
    await rotator.move_position_angle(90.0)
    assert 18.0 <= observatory.clock.time() - start < 25.0  # 90° at 5°/s, plus loop latency
    assert await rotator.get_position_angle() == pytest.approx(90.0)
    start = observatory.clock.time()
    await rotator.move_position_angle_by(-100.0)  # through 0°, not the long way
    assert 20.0 <= observatory.clock.time() - start < 27.0
    assert await rotator.get_position_angle() == pytest.approx(350.0)
    await rotator.move_mechanical(-20.0)
    assert await rotator.get_mechanical_angle() == pytest.approx(340.0)
    assert await rotator.get_motion_status() is MotionStatus.IDLE


async def test_sky_offset_and_reversal(observatory: Observatory) -> None:
    rotator = await observatory.start(SimRotator, "rotator", speed=50.0, sky_offset=10.0)
    await rotator.move_position_angle(40.0)
    assert await rotator.get_mechanical_angle() == pytest.approx(30.0)
    await rotator.set_rotator_reversed(True)
    assert await rotator.get_rotator_reversed() is True
    await rotator.move_position_angle(40.0)
    assert await rotator.get_mechanical_angle() == pytest.approx(330.0)
    assert await rotator.get_position_angle() == pytest.approx(40.0)
    cards = await rotator.get_fits_header_before()
    assert cards["ROTPA"][0] == pytest.approx(40.0) and cards["ROTMECH"][0] == pytest.approx(330.0)


async def test_halt_stops_a_move_where_it_is(observatory: Observatory) -> None:
    rotator = await observatory.start(SimRotator, "rotator", speed=1.0)
    moving = asyncio.create_task(rotator.move_position_angle(120.0))
    await observatory.wait_for(lambda: rotator.mechanical > 10.0, 60.0)
    with pytest.raises(DeviceBusyError, match="busy"):
        await rotator.move_mechanical(0.0)
    await rotator.stop_motion()
    with pytest.raises(AbortedError, match="was aborted"):
        await moving
    angle = await rotator.get_mechanical_angle()
    assert 10.0 < angle < 120.0
    assert await rotator.get_motion_status() is MotionStatus.IDLE


@pytest.mark.parametrize("angle", [math.nan, math.inf])
async def test_impossible_angles_are_refused(observatory: Observatory, angle: float) -> None:
    rotator = await observatory.start(SimRotator, "rotator")
    for move in (rotator.move_position_angle, rotator.move_position_angle_by, rotator.move_mechanical):
        with pytest.raises(InvalidArgumentError, match="the angle must be a finite number of degrees"):
            await move(angle)
    assert await rotator.get_mechanical_angle() == 0.0


async def test_a_half_turn_ends_within_the_announced_timeout(observatory: Observatory) -> None:
    rotator = await observatory.start(SimRotator, "rotator", speed=1.0)
    probe = await observatory.start(ContractProbe, "probe")
    announced, took = await timed_call(ContractSetup(rotator, probe), "move_position_angle", 180.0)
    assert announced == 300 and 180.0 <= took < announced
    assert isinstance(await probe.comm.proxy("rotator", IRotator), IRotator)
