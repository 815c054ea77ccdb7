"""One PANEL_FLAT task in real time against the simulated camera, for the tests that put a real
device's light (Alpaca, INDI) in front of it: the camera renders what the module ``calibrator``
does."""

from __future__ import annotations

import numpy as np
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.robotic.scripts import PanelFlatScript
from nightcrew.testing import Observatory
from tests.robotic.runner_sim import ProgressLog, make_task, start_sim

__all__ = ["BIAS", "run_one_panel_flat"]

BIAS = 1000.0  # ADU, the simulated camera's


async def run_one_panel_flat(obs: Observatory, level: float) -> tuple[fits.Header, float]:
    """Take one V flat at ``level`` ADU; its FITS header and its median."""
    # A bright panel, so that the real-time exposures stay short.
    sim = await start_sim(obs, calibrator="calibrator", panel_e_per_s=500000.0)
    runner = await sim.runner({"PANEL_FLAT": PanelFlatScript(min_exposure=0.02, max_exposure=2.0)})
    flats = {
        "type": "PANEL_FLAT",
        "extra_params": {"level": level},
        "instrument_configs": [
            {"exposure_time": 0.05, "exposure_count": 1, "optical_elements": {"filter": "V"}}
        ],
    }
    await runner.run_task(make_task(flats), ProgressLog())
    (header,) = await sim.headers(1)
    median = float(np.median((await obs.vfs.read_fits(sim.frames[0]))[0].data))
    return header, median
