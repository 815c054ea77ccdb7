"""BaseCoverCalibrator through SimCoverCalibrator: a dome-flat sequence, timing, refusals, halting."""

from __future__ import annotations

import asyncio

import pytest

from nightcrew.errors import InvalidArgumentError, MoveError, NotSupportedError
from nightcrew.interfaces import CalibratorState, CoverState, ICoverCalibrator
from nightcrew.modules.sim import SimCoverCalibrator
from nightcrew.testing import EventRecorder, Observatory


async def _flats(observatory: Observatory, **options: object) -> ICoverCalibrator:
    probe = await observatory.start(EventRecorder, "probe", types=[])
    await observatory.start(SimCoverCalibrator, "flats", **options)
    return await probe.comm.proxy("flats", ICoverCalibrator)


async def test_dome_flat_sequence_waits_for_cover_and_light(observatory: Observatory) -> None:
    flats = await _flats(observatory, cover_time=20.0, warmup_time=8.0, max_brightness=100)
    await flats.open_cover()
    start = observatory.clock.time()
    await flats.close_cover()
    assert 20.0 <= observatory.clock.time() - start < 25.0
    assert await flats.get_cover_state() is CoverState.CLOSED
    start = observatory.clock.time()
    await flats.calibrator_on(60)
    assert 8.0 <= observatory.clock.time() - start < 13.0  # returns only once the light is stable
    assert (await flats.get_calibrator_state(), await flats.get_brightness()) == (CalibratorState.READY, 60)
    await flats.calibrator_off()
    assert (await flats.get_calibrator_state(), await flats.get_brightness()) == (CalibratorState.OFF, 0)
    await flats.open_cover()
    assert await flats.get_cover_state() is CoverState.OPEN


@pytest.mark.parametrize("brightness", [-1, 101])
async def test_brightness_beyond_the_range_is_refused(observatory: Observatory, brightness: int) -> None:
    flats = await _flats(observatory, max_brightness=100)
    with pytest.raises(
        InvalidArgumentError, match=f"brightness must be an integer within 0..100, got {brightness}"
    ):
        await flats.calibrator_on(brightness)
    assert await flats.get_calibrator_state() is CalibratorState.OFF


async def test_missing_parts_are_refused(observatory: Observatory) -> None:
    panel = await _flats(observatory, cover=False)
    assert await panel.get_cover_state() is CoverState.NOT_PRESENT
    for call in (panel.open_cover(), panel.close_cover(), panel.halt_cover()):
        with pytest.raises(NotSupportedError, match="flats has no cover"):
            await call
    await panel.calibrator_on(1)
    assert await panel.get_calibrator_state() is CalibratorState.READY


async def test_a_dust_cover_has_no_light(observatory: Observatory) -> None:
    cover = await _flats(observatory, light=False)
    assert await cover.get_calibrator_state() is CalibratorState.NOT_PRESENT
    for call in (cover.calibrator_on(10), cover.calibrator_off(), cover.get_max_brightness()):
        with pytest.raises(NotSupportedError, match="flats has no flat-field light"):
            await call


async def test_a_cover_halted_halfway_is_unknown_and_the_move_fails(observatory: Observatory) -> None:
    flats = await _flats(observatory, cover_time=60.0)
    module = observatory.module("flats", SimCoverCalibrator)
    opening = asyncio.create_task(flats.open_cover())
    await observatory.wait_for(lambda: module.cover is CoverState.MOVING, 30.0)
    await flats.halt_cover()
    with pytest.raises(MoveError, match="flats: the cover is unknown, not open"):
        await opening
    assert await flats.get_cover_state() is CoverState.UNKNOWN
    await flats.close_cover()  # and it moves again
    assert await flats.get_cover_state() is CoverState.CLOSED
