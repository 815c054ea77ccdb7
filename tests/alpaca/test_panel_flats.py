"""PANEL_FLAT with alpaca-simulators' flip-flat through the Alpaca bridge: the script drives the real
device (cover, light), and the simulated camera renders what that device does (real time)."""

from __future__ import annotations

import numpy as np

from nightcrew.clock import RealClock
from nightcrew.interfaces import CalibratorState, CoverState
from nightcrew.modules.alpaca import AlpacaCoverCalibrator
from nightcrew.robotic.scripts import PanelFlatScript
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile
from tests.robotic.runner_sim import ProgressLog, make_task, start_sim

from .more_devices import FLIP_FLAT

LEVEL = 20000.0


async def test_panel_flats_on_the_alpaca_flip_flat(more_devices_url: str) -> None:
    async with Observatory(clock=RealClock()) as obs:
        try:
            calibrator = await obs.start(
                AlpacaCoverCalibrator, "calibrator", server=more_devices_url, device_number=FLIP_FLAT
            )
            # A bright panel, so that the real-time exposures stay short.
            sim = await start_sim(obs, calibrator="calibrator", panel_e_per_s=500000.0)
            runner = await sim.runner({"PANEL_FLAT": PanelFlatScript(min_exposure=0.02, max_exposure=2.0)})
            flats = {
                "type": "PANEL_FLAT",
                "extra_params": {"level": LEVEL},
                "instrument_configs": [
                    {"exposure_time": 0.05, "exposure_count": 1, "optical_elements": {"filter": "V"}}
                ],
            }
            await runner.run_task(make_task(flats), ProgressLog())
            (header,) = await sim.headers(1)
            assert header["IMAGETYP"] == "domeflat"
            level = float(np.median((await obs.vfs.read_fits(sim.frames[0]))[0].data))
            assert abs(level - LEVEL) <= 0.1 * (LEVEL - 1000.0)
            assert await calibrator.get_cover_state() is CoverState.OPEN
            assert await calibrator.get_calibrator_state() is CalibratorState.OFF
        finally:
            MemoryFile.clear_shared()
