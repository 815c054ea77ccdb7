"""PANEL_FLAT with alpaca-simulators' flip-flat through the Alpaca bridge: the script drives the real
device (cover, light), and the simulated camera renders what that device does (real time)."""

from __future__ import annotations

from nightcrew.clock import RealClock
from nightcrew.interfaces import CalibratorState, CoverState
from nightcrew.modules.alpaca import AlpacaCoverCalibrator
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile
from tests.robotic.panel_flat_run import BIAS, run_one_panel_flat

from .more_devices import FLIP_FLAT

LEVEL = 20000.0


async def test_panel_flats_on_the_alpaca_flip_flat(more_devices_url: str) -> None:
    async with Observatory(clock=RealClock()) as obs:
        try:
            calibrator = await obs.start(
                AlpacaCoverCalibrator, "calibrator", server=more_devices_url, device_number=FLIP_FLAT
            )
            header, level = await run_one_panel_flat(obs, LEVEL)
            assert header["IMAGETYP"] == "domeflat"
            assert abs(level - LEVEL) <= 0.1 * (LEVEL - BIAS)
            assert await calibrator.get_cover_state() is CoverState.OPEN
            assert await calibrator.get_calibrator_state() is CalibratorState.OFF
        finally:
            MemoryFile.clear_shared()
