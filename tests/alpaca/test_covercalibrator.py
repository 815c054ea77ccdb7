"""AlpacaCoverCalibrator against alpaca-simulators' CoverCalibrator: what a dome-flat script does
(close the cover, light on, flats, light off, open), and the parts a device lacks."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator, Iterator
from pathlib import Path

import pytest

from nightcrew.clock import RealClock
from nightcrew.errors import InvalidArgumentError, NotSupportedError
from nightcrew.interfaces import CalibratorState, CoverState, ICoverCalibrator
from nightcrew.modules.alpaca.covercalibrator import AlpacaCoverCalibrator
from nightcrew.testing import EventRecorder, Observatory

from .more_devices import FLIP_FLAT, PANEL, start_with_more_devices


@pytest.fixture(scope="module")
def alpaca_server(tmp_path_factory: pytest.TempPathFactory, alpaca_star_table: Path) -> Iterator[str]:
    """A private simulator with the extra devices (see more_devices), for this file's tests."""
    with start_with_more_devices(tmp_path_factory.mktemp("alpaca-more"), alpaca_star_table) as simulator:
        yield simulator.url


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    async with Observatory(clock=RealClock()) as obs:
        yield obs


async def _proxy(obs: Observatory, alpaca_server: str, device_number: int) -> ICoverCalibrator:
    probe = await obs.start(EventRecorder, "probe", types=[])
    await obs.start(AlpacaCoverCalibrator, "flats", server=alpaca_server, device_number=device_number)
    return await probe.comm.proxy("flats", ICoverCalibrator)


async def test_dome_flat_sequence(observatory: Observatory, alpaca_server: str) -> None:
    flats = await _proxy(observatory, alpaca_server, FLIP_FLAT)
    await flats.close_cover()
    assert await flats.get_cover_state() is CoverState.CLOSED
    maximum = await flats.get_max_brightness()
    assert maximum == 255
    await flats.calibrator_on(maximum // 2)
    assert await flats.get_calibrator_state() is CalibratorState.READY
    assert await flats.get_brightness() == 127
    await flats.calibrator_off()
    assert await flats.get_calibrator_state() is CalibratorState.OFF
    assert await flats.get_brightness() == 0
    await flats.open_cover()
    assert await flats.get_cover_state() is CoverState.OPEN


@pytest.mark.parametrize("brightness", [-1, 256])
async def test_brightness_beyond_the_maximum_is_refused(
    observatory: Observatory, alpaca_server: str, brightness: int
) -> None:
    flats = await _proxy(observatory, alpaca_server, FLIP_FLAT)
    with pytest.raises(
        InvalidArgumentError, match=f"brightness must be an integer within 0..255, got {brightness}"
    ):
        await flats.calibrator_on(brightness)


async def test_device_error_reply_names_device_and_call(observatory: Observatory, alpaca_server: str) -> None:
    # The simulator's cover moves synchronously, so it answers HaltCover with NotImplemented (0x400).
    flats = await _proxy(observatory, alpaca_server, FLIP_FLAT)
    with pytest.raises(
        NotSupportedError,
        match=re.escape(
            f"covercalibrator 0 at {alpaca_server}: PUT haltcover: NotImplemented (0x400): HaltCover"
        ),
    ):
        await flats.halt_cover()
    module = observatory.module("flats", AlpacaCoverCalibrator)
    assert await module.get_state() == "ready"  # one refused call is no reason to give up the device


async def test_a_panel_without_cover_refuses_cover_calls(
    observatory: Observatory, alpaca_server: str
) -> None:
    panel = await _proxy(observatory, alpaca_server, PANEL)
    assert await panel.get_cover_state() is CoverState.NOT_PRESENT
    for call in (panel.open_cover(), panel.close_cover(), panel.halt_cover()):
        with pytest.raises(NotSupportedError, match=f"covercalibrator 1 at {alpaca_server} has no cover"):
            await call
    await panel.calibrator_on(10)
    assert await panel.get_calibrator_state() is CalibratorState.READY
    await panel.calibrator_off()
