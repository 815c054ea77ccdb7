"""AlpacaRotator against alpaca-simulators' Rotator: moves, angles, reversing, halting, FITS cards."""

from __future__ import annotations

import math
from collections.abc import AsyncIterator

import pytest

from nightcrew.clock import RealClock
from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.events import MotionStatusChangedEvent
from nightcrew.interfaces import IRotator, MotionStatus
from nightcrew.modules.alpaca.rotator import AlpacaRotator
from nightcrew.testing import EventRecorder, Observatory
from nightcrew.testing.alpaca import AlpacaSimulator
from nightcrew.timeout import method_timeout


@pytest.fixture
def alpaca_server(alpaca_simulator: AlpacaSimulator) -> str:
    return alpaca_simulator.url


@pytest.fixture
async def rotator(alpaca_server: str) -> AsyncIterator[tuple[AlpacaRotator, EventRecorder]]:
    async with Observatory(clock=RealClock()) as obs:
        recorder = await obs.start(EventRecorder, "recorder", types=[MotionStatusChangedEvent])
        module = await obs.start(AlpacaRotator, "rotator", server=alpaca_server)
        yield module, recorder
        await module.set_rotator_reversed(False)


async def test_moves_to_a_position_angle_and_by_an_offset(
    rotator: tuple[AlpacaRotator, EventRecorder],
) -> None:
    module, recorder = rotator
    await module.move_position_angle(123.4)
    assert await module.get_position_angle() == pytest.approx(123.4)
    await module.move_position_angle_by(-30.0)
    assert await module.get_position_angle() == pytest.approx(93.4)
    await module.move_position_angle(-10.0)  # the same as 350°
    assert await module.get_position_angle() == pytest.approx(350.0)
    await module.move_position_angle_by(20.0)  # across 0°
    assert await module.get_position_angle() == pytest.approx(10.0)
    assert await module.get_motion_status() is MotionStatus.IDLE
    await recorder.wait_for_event(
        MotionStatusChangedEvent, 10.0, sender="rotator", where=lambda e: e.status is MotionStatus.MOVING
    )


async def test_mechanical_angle_and_fits_cards(rotator: tuple[AlpacaRotator, EventRecorder]) -> None:
    module, _ = rotator
    await module.move_mechanical(200.0)
    assert await module.get_mechanical_angle() == pytest.approx(200.0)
    cards = await module.get_fits_header_before()
    assert cards["ROTMECH"] == (200.0, "Rotator mechanical angle [deg]")
    assert cards["ROTPA"][0] == pytest.approx(await module.get_position_angle())


async def test_reverse_is_set_and_read_back(rotator: tuple[AlpacaRotator, EventRecorder]) -> None:
    module, _ = rotator
    await module.set_rotator_reversed(True)
    assert await module.get_rotator_reversed() is True
    assert await module.device.get("reverse") is True
    await module.set_rotator_reversed(False)
    assert await module.get_rotator_reversed() is False


@pytest.mark.parametrize("angle", [math.nan, math.inf, -math.inf])
async def test_impossible_angles_are_refused_before_the_device(
    rotator: tuple[AlpacaRotator, EventRecorder], angle: float
) -> None:
    module, _ = rotator
    before = await module.get_position_angle()
    for move in (module.move_position_angle, module.move_position_angle_by, module.move_mechanical):
        with pytest.raises(InvalidArgumentError, match="the angle must be a finite number of degrees"):
            await move(angle)
    assert await module.get_position_angle() == pytest.approx(before)


async def test_stop_motion_halts_the_device(rotator: tuple[AlpacaRotator, EventRecorder]) -> None:
    module, _ = rotator
    await module.stop_motion()
    assert await module.device.get("ismoving") is False
    assert await module.get_motion_status() is MotionStatus.IDLE
    await module.park()  # nothing to park: stays where it is and usable
    assert await module.is_ready()


def test_moves_announce_a_timeout_longer_than_the_module_waits() -> None:
    module = AlpacaRotator(name="rotator", server="http://127.0.0.1:1")
    assert module._move_timeout < method_timeout(IRotator.move_position_angle, {})
    with pytest.raises(
        ConfigError,
        match=r"key 'move_timeout': must be within 0\.\.300 seconds \(the announced timeout\), got 300",
    ):
        AlpacaRotator(name="rotator", server="http://127.0.0.1:1", move_timeout=300)
