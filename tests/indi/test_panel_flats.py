"""PANEL_FLAT with indi_simulator_lightpanel (a light without a cover) through IndiCoverCalibrator:
the script switches the real INDI light on and off and leaves the missing cover alone; the
simulated camera renders what that light does (the INDI CCD simulator renders no panel), so the
flat level is really reached (real time)."""

from __future__ import annotations

from nightcrew.clock import RealClock
from nightcrew.interfaces import CalibratorState, CoverState
from nightcrew.modules.indi import IndiCoverCalibrator
from nightcrew.testing import Observatory
from nightcrew.testing.indi import SIMULATORS, IndiServer
from nightcrew.vfs import MemoryFile
from tests.robotic.panel_flat_run import BIAS, run_one_panel_flat

LEVEL = 20000.0


async def test_panel_flats_on_the_indi_light_panel(indi_server: IndiServer) -> None:
    async with Observatory(clock=RealClock()) as obs:
        try:
            calibrator = await obs.start(
                IndiCoverCalibrator,
                "calibrator",
                host=indi_server.host,
                port=indi_server.port,
                device=SIMULATORS["indi_simulator_lightpanel"],
            )
            assert await calibrator.get_cover_state() is CoverState.NOT_PRESENT
            header, level = await run_one_panel_flat(obs, LEVEL)
            assert header["IMAGETYP"] == "domeflat"
            assert abs(level - LEVEL) <= 0.1 * (LEVEL - BIAS)
            assert await calibrator.get_calibrator_state() is CalibratorState.OFF
            assert calibrator._indi.vector("FLAT_LIGHT_CONTROL").on_switches() == ["FLAT_LIGHT_OFF"]
        finally:
            MemoryFile.clear_shared()
