"""TaskRunner on the simulated observatory: scripts by configuration type, progress, errors."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.errors import ConfigError, NotSupportedError
from nightcrew.robotic.runner import TaskRunner, configuration_task, merged_progress
from nightcrew.robotic.scripts import ImagingScript
from nightcrew.robotic.tasks import TaskProgress

from .runner_sim import PLEIADES, ProgressLog, SimSetup, make_task, sim

__all__ = ["sim"]

IMAGING = {"class": "nightcrew.robotic.scripts.ImagingScript"}


def expose(*filters: str, count: int = 2, exposure_time: float = 1.0, binning: int = 2) -> dict[str, object]:
    return {
        "type": "EXPOSE",
        "target": PLEIADES,
        "instrument_configs": [
            {
                "exposure_time": exposure_time * (n + 1),
                "exposure_count": count,
                "optical_elements": {"filter": name},
                "binning": binning,
            }
            for n, name in enumerate(filters)
        ],
    }


async def test_expose_takes_every_frame_with_its_filter_and_time_and_reports_each(sim: SimSetup) -> None:
    runner = await sim.runner({"EXPOSE": IMAGING})
    task = make_task(expose("V", "R"))
    assert isinstance(runner.script_for(task), ImagingScript)
    assert await runner.can_run(task)
    progress = ProgressLog()

    await runner.run_task(task, progress)

    headers = await sim.headers(4)
    assert [(h["FILTER"], h["EXPTIME"], h["IMAGETYP"]) for h in headers] == [
        ("V", 1.0, "object"),
        ("V", 1.0, "object"),
        ("R", 2.0, "object"),
        ("R", 2.0, "object"),
    ]
    assert all(h["NAXIS1"] == 128 for h in headers)  # binned 2x2
    assert [p.exposures_done for p in progress.reports] == [((1, 0),), ((2, 0),), ((2, 1),), ((2, 2),)]
    assert progress.last.configuration_complete(task.request, 0)


async def test_a_type_without_script_is_not_supported_and_named(sim: SimSetup) -> None:
    runner = await sim.runner({"EXPOSE": IMAGING})
    task = make_task({"type": "BIAS", "instrument_configs": [{"exposure_time": 0, "exposure_count": 1}]})
    with pytest.raises(NotSupportedError, match="no script configured for BIAS configurations"):
        runner.script_for(task)
    assert not await runner.can_run(task)
    with pytest.raises(NotSupportedError, match="BIAS"):
        await runner.run_task(task, ProgressLog())
    assert sim.frames == []


def test_bad_script_keys_are_config_errors_naming_the_key() -> None:
    with pytest.raises(ConfigError, match=r"key 'scripts\.EXPOSURE': unknown configuration type"):
        TaskRunner(scripts={"EXPOSURE": IMAGING})
    with pytest.raises(ConfigError, match=r"key 'scripts\.SCRIPT:'"):
        TaskRunner(scripts={"SCRIPT:": IMAGING})


def test_the_example_runner_config_validates_and_builds_every_script() -> None:
    path = Path(__file__).parents[2] / "examples" / "robotic" / "runner.yaml"
    config = load_config(path)
    validate_config(config, TaskRunner)
    runner = build_object(config, TaskRunner)
    assert {key: type(script).__name__ for key, script in runner.scripts.items()} == {
        "EXPOSE": "ImagingScript",
        "REPEAT_EXPOSE": "ImagingScript",
        "BIAS": "CalibrationScript",
        "DARK": "CalibrationScript",
        "AUTO_FOCUS": "AutoFocusScript",
        "SKY_FLAT": "SkyFlatScript",
        "SCRIPT:pointing": "PointingSeriesScript",
    }


def test_a_task_is_narrowed_to_one_configuration_and_its_progress_put_back() -> None:
    task = make_task(expose("V", "R"), {"type": "BIAS", "instrument_configs": [{"exposure_time": 0}]})
    second = configuration_task(task, 1)
    assert [c.type.value for c in second.request.configurations] == ["BIAS"]
    done = merged_progress(TaskProgress.nothing_done(task.request), 1, TaskProgress(exposures_done=((1,),)))
    assert done.exposures_done == ((0, 0), (1,))
