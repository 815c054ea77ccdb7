"""docs/mounts.md: its simulated GEM passes ``nightcrew check`` as written, and its bad limits give
the error line it shows."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
import yaml

from nightcrew.cli.main import main
from nightcrew.config import build_object
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.scripts import ImagingScript

DOC = (Path(__file__).parents[2] / "docs/mounts.md").read_text(encoding="utf-8")


def _block(language: str, index: int = 0) -> str:
    blocks = re.findall(rf"^```{language}\n(.*?)^```", DOC, flags=re.M | re.S)
    assert len(blocks) > index, f"no {language} block {index} in docs/mounts.md"
    return str(blocks[index])


def test_the_documented_gem_passes_check_and_its_bad_limits_give_the_documented_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    config = _block("yaml")
    Path("telescope.yaml").write_text(config, encoding="utf-8")
    assert main(["check", "telescope.yaml"]) == 0, capsys.readouterr().err
    capsys.readouterr()

    command, expected = _block("console").splitlines()[:2]
    east = re.search(r"got east (\S+)°", expected)
    assert east is not None
    bad = re.sub(r"east: -?[\d.]+", f"east: {east.group(1)}", config, count=1)
    Path("telescope.yaml").write_text(bad, encoding="utf-8")
    assert main(shlex.split(command.removeprefix("$ nightcrew "))) == 2
    assert capsys.readouterr().err.splitlines() == [expected]


def test_the_documented_flip_option_builds_the_runner_it_shows() -> None:
    runner = build_object(yaml.safe_load(_block("yaml", 1))["runner"])
    assert isinstance(runner, TaskRunner)
    for script in runner.scripts.values():
        assert isinstance(script, ImagingScript) and script.flip_past_meridian == 5.0


def test_the_documented_guider_after_a_flip_passes_check(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    config = _block("yaml", 2)
    assert config.startswith("# guiding.yaml\n") and "pier_side: east" in config
    Path("guiding.yaml").write_text(config, encoding="utf-8")
    assert main(["check", "guiding.yaml"]) == 0, capsys.readouterr().err
