"""A science frame of a German-equatorial mount and a cooled camera carries every card issue 27 asks for:
PIERSIDE, CCD-TEMP, SET-TEMP, COOLPOW, TEMP-OK, DATE-END (OBJECT comes from the mastermind:
tests/robotic/test_mastermind_sim.py)."""

from __future__ import annotations

from datetime import datetime

import pytest

from nightcrew.robotic.scripts import ImagingScript
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile

from .runner_sim import PLEIADES, ProgressLog, make_task, start_sim

GEM = {"east": -100.0, "west": 100.0, "counterweight_up": 10.0}


async def test_a_science_frame_has_pier_side_cooling_and_end_cards() -> None:
    async with Observatory() as obs:
        try:
            sim = await start_sim(
                obs, telescope_options={"gem": GEM}, cooler={"ambient": 8.0, "max_delta": 35.0}
            )
            await sim.camera.set_cooling(True, -10.0)
            await obs.clock.sleep(900.0)  # at the set point
            runner = await sim.runner({"EXPOSE": ImagingScript()})
            frames = {"exposure_time": 5.0, "exposure_count": 1, "optical_elements": {"filter": "V"}}
            await runner.run_task(
                make_task({"type": "EXPOSE", "target": PLEIADES, "instrument_configs": [frames]}),
                ProgressLog(),
            )
            (header,) = await sim.headers(1)
        finally:
            MemoryFile.clear_shared()
    assert header["PIERSIDE"] in ("EAST", "WEST")
    assert header["CCD-TEMP"] == pytest.approx(-10.0, abs=0.5) and header["SET-TEMP"] == -10.0
    assert 0 < header["COOLPOW"] <= 100 and header["TEMP-OK"] is True
    start, end = (datetime.fromisoformat(header[key]) for key in ("DATE-OBS", "DATE-END"))
    assert (end - start).total_seconds() == pytest.approx(header["EXPTIME"], abs=0.002)
