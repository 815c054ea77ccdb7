"""docs/mounts.md: its simulated GEM passes ``nightcrew check`` as written, and its bad limits give
the error line it shows."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from nightcrew.cli.main import main

DOC = (Path(__file__).parents[2] / "docs/mounts.md").read_text(encoding="utf-8")


def _block(language: str) -> str:
    match = re.search(rf"^```{language}\n(.*?)^```", DOC, flags=re.M | re.S)
    assert match is not None, f"no {language} block in docs/mounts.md"
    return match.group(1)


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
