"""Dithering: the patterns (pure), the task's dither_config, and docs/tasks.md's "Dithering" as written."""

from __future__ import annotations

import itertools
import math
import re
import shlex
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.robotic.scripts._dither import SPIRAL_STEPS, dither_offset, dither_to_radec, dithers_before
from nightcrew.robotic.tasks import DitherConfig, DitherPattern, InvalidTaskError, parse_request_group

from .runner_sim import request_group

DOC = (Path(__file__).parents[2] / "docs/tasks.md").read_text(encoding="utf-8")


def test_the_spiral_steps_by_the_amplitude_along_one_axis_and_comes_back() -> None:
    config = DitherConfig(pattern=DitherPattern.SPIRAL, amplitude=20.0, every=2)
    positions = [dither_offset(config, index) for index in range(2 * len(SPIRAL_STEPS) + 1)]
    assert positions[0] == (0.0, 0.0) and len(set(positions)) == len(SPIRAL_STEPS)
    for (e0, n0), (e1, n1) in itertools.pairwise(positions[1:9]):
        assert sorted((abs(e1 - e0), abs(n1 - n0))) == [0.0, 20.0]  # one step along one axis
    assert max(math.hypot(*p) for p in positions) == pytest.approx(20.0 * math.sqrt(2.0))
    assert positions[9] == (0.0, 0.0)  # round again
    assert [dithers_before(config, frames) for frames in range(6)] == [0, 0, 1, 1, 2, 2]


def test_random_positions_stay_within_the_amplitude_and_repeat_for_the_same_task() -> None:
    config = DitherConfig(pattern=DitherPattern.RANDOM, amplitude=15.0)
    positions = [dither_offset(config, index, seed="task-1") for index in range(1, 200)]
    assert all(abs(e) <= 15.0 and abs(n) <= 15.0 for e, n in positions)
    assert max(abs(e) for e, _ in positions) > 12.0 and len(set(positions)) == len(positions)
    assert positions == [dither_offset(config, index, seed="task-1") for index in range(1, 200)]
    assert positions != [dither_offset(config, index, seed="task-2") for index in range(1, 200)]
    assert dither_offset(DitherConfig(amplitude=0.0), 5) == (0.0, 0.0)  # no dithering


def test_an_offset_east_is_a_longer_step_along_the_ra_axis_away_from_the_equator() -> None:
    dra, ddec = dither_to_radec((36.0, 18.0), 60.0)
    assert dra == pytest.approx(0.02) and ddec == pytest.approx(0.005)


def test_a_dither_outside_exposures_or_out_of_range_is_refused_naming_the_field() -> None:
    bias = {"type": "BIAS", "dither_config": {"amplitude": 10}, "instrument_configs": [{"exposure_time": 0}]}
    with pytest.raises(InvalidTaskError, match=r"dither_config.amplitude: dithering is only for EXPOSE"):
        parse_request_group(request_group(bias))
    frames = [{"exposure_time": 10}]
    target = {"name": "M15", "ra": 322.493, "dec": 12.167}
    for bad, where in (
        ({"every": 0}, "every"),
        ({"pattern": "CIRCLE"}, "pattern"),
        ({"amplitude": -1}, "amplitude"),
    ):
        expose = {"type": "EXPOSE", "target": target, "dither_config": bad, "instrument_configs": frames}
        with pytest.raises(InvalidTaskError, match=rf"dither_config.{where}"):
            parse_request_group(request_group(expose))


def _block(language: str, after: str) -> str:
    section = DOC.split(after, 1)[1]
    match = re.search(rf"^```{language}\n(.*?)^```", section, flags=re.M | re.S)
    assert match is not None, f"no {language} block after {after!r} in docs/tasks.md"
    return match.group(1)


def test_check_refuses_a_dither_larger_than_the_field_as_docs_tasks_shows(
    observatory_copy: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(observatory_copy)
    task = _block("yaml", "## Dithering")
    command, expected = _block("console", "## Dithering").splitlines()[:2]
    Path("dithered.yaml").write_text(task, encoding="utf-8")
    args = shlex.split(command.removeprefix("$ nightcrew "))
    assert main(args) == 0, capsys.readouterr().err
    amplitude = re.search(r'amplitude: (\d+)"', expected)
    assert amplitude is not None
    Path("dithered.yaml").write_text(
        task.replace("amplitude: 20", f"amplitude: {amplitude[1]}"), encoding="utf-8"
    )
    capsys.readouterr()
    assert main(args) == 2
    assert capsys.readouterr().err.splitlines() == [expected]
