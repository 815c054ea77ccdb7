"""PANEL_FLAT: cover closed, light on, the exposure found per filter, flats taken, light off, open."""

from __future__ import annotations

import re
from collections.abc import AsyncIterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from nightcrew.config import build_object
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.interfaces import CalibratorState, CoverState
from nightcrew.modules.sim import SimCoverCalibrator
from nightcrew.robotic.runner import Script, ScriptError
from nightcrew.robotic.scripts import PanelFlatScript
from nightcrew.robotic.tasks import parse_request_group, tasks_of_group
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile

from .runner_sim import ProgressLog, SimSetup, make_task, request_group, start_sim

DOC = (Path(__file__).parents[2] / "docs" / "tasks.md").read_text(encoding="utf-8")
_BLOCKS = re.findall(r"```yaml\n(.*?)```", DOC.split("## Panel flats", 1)[1].split("\n## ", 1)[0], flags=re.S)
#: docs/tasks.md, "Panel flats": the task file and the runner's PANEL_FLAT entry, as written there.
TASK_FILE, RUNNER = (yaml.safe_load(block) for block in _BLOCKS)
PANEL_FLATS = TASK_FILE["requests"][0]["configurations"][0]
LEVEL = float(PANEL_FLATS["extra_params"]["level"])


def documented_script(**changes: Any) -> PanelFlatScript:
    """The PANEL_FLAT script as docs/tasks.md configures it, with ``changes``."""
    script = build_object({**RUNNER["runner"]["scripts"]["PANEL_FLAT"], **changes}, Script)
    assert isinstance(script, PanelFlatScript)
    return script


@pytest.fixture
async def panel_sim() -> AsyncIterator[SimSetup]:
    obs = Observatory()
    try:
        await obs.start(SimCoverCalibrator, "calibrator", cover_time=2.0, warmup_time=1.0)
        # Throughputs differ per filter, so each filter needs its own exposure time.
        yield await start_sim(obs, calibrator="calibrator", filter_throughputs={"V": 0.8, "R": 0.4})
    finally:
        await obs.close()
        MemoryFile.clear_shared()


async def test_panel_flats_reach_the_level_in_every_filter_and_leave_the_telescope_open(
    panel_sim: SimSetup,
) -> None:
    calibrator = panel_sim.obs.module("calibrator", SimCoverCalibrator)
    await calibrator.open_cover()
    runner = await panel_sim.runner({"PANEL_FLAT": documented_script()})
    progress = ProgressLog()
    group = parse_request_group(TASK_FILE)
    await runner.run_task(tasks_of_group(group, "g1", ["t1"])[0], progress)

    assert progress.last.exposures_done == ((2, 2),)
    headers = await panel_sim.headers(4)  # the announced flats only: no test frames, no bias
    assert [h["IMAGETYP"] for h in headers] == ["domeflat"] * 4
    assert [h["FILTER"] for h in headers] == ["V", "V", "R", "R"]
    levels = [float(np.median((await panel_sim.obs.vfs.read_fits(f))[0].data)) for f in panel_sim.frames]
    bias = 1000.0  # the simulated detector's
    print(f"\nlevels {levels}, exposures {[h['EXPTIME'] for h in headers]}")
    assert all(abs(level - LEVEL) <= 0.1 * (LEVEL - bias) for level in levels)
    assert headers[2]["EXPTIME"] == pytest.approx(2 * headers[0]["EXPTIME"], rel=0.1)  # R passes half
    assert calibrator.cover is CoverState.OPEN and calibrator.light is CalibratorState.OFF
    # The bias and test frames are gone (they would go into a master flat); the flats are there.
    vfs = panel_sim.obs.vfs
    assert await vfs.find("/cache/**/*-domeflat*.fits") == sorted(panel_sim.frames)
    assert await vfs.find("/cache/**/*-bias*.fits") == []


async def test_a_panel_too_faint_for_the_level_fails_naming_it_and_still_opens(panel_sim: SimSetup) -> None:
    calibrator = panel_sim.obs.module("calibrator", SimCoverCalibrator)
    runner = await panel_sim.runner({"PANEL_FLAT": documented_script(brightness=1, max_exposure=2)})
    with pytest.raises(ScriptError, match=r"the panel is too faint for 30000 ADU: \d+ ADU in 2 s"):
        await runner.run_task(make_task(PANEL_FLATS), ProgressLog())
    assert calibrator.cover is CoverState.OPEN and calibrator.light is CalibratorState.OFF


def test_a_flat_level_above_saturation_is_refused_when_the_task_is_added() -> None:
    too_bright = {**PANEL_FLATS, "extra_params": {"level": 70000}}
    with pytest.raises(
        NightcrewError, match=r"extra_params.level.*70000 ADU is at or above saturation \(65535"
    ):
        parse_request_group(request_group(too_bright))


def test_a_script_level_above_saturation_is_refused_at_check() -> None:
    with pytest.raises(ConfigError, match=r"key 'level': 70000 ADU is not below saturation \(65535 ADU\)"):
        documented_script(level=70000)
