"""docs/mounts.md, Centring: the documented acquisition passes ``nightcrew check`` as written, its
bad tolerance gives the documented line, and a target pixel beyond the camera's chip is named."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest

from nightcrew.cli.main import main

DOC = (Path(__file__).parents[2] / "docs/mounts.md").read_text(encoding="utf-8")
SECTION = DOC[DOC.index("\n## Centring\n") :]


def _block(language: str) -> str:
    blocks = re.findall(rf"^```{language}\n(.*?)^```", SECTION, flags=re.M | re.S)
    assert blocks, f"no {language} block in the Centring section of docs/mounts.md"
    return str(blocks[0])


def test_the_documented_acquisition_passes_check_and_its_bad_tolerance_gives_the_documented_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    config = _block("yaml")
    Path("acquisition.yaml").write_text(config, encoding="utf-8")
    assert main(["check", "acquisition.yaml"]) == 0, capsys.readouterr().err
    capsys.readouterr()

    command, expected = _block("console").splitlines()[:2]
    got = re.search(r"got (\S+)\"$", expected)
    assert got is not None
    bad = re.sub(r"^tolerance: [\d.]+", f"tolerance: {got.group(1)}", config, count=1, flags=re.M)
    Path("acquisition.yaml").write_text(bad, encoding="utf-8")
    assert main(shlex.split(command.removeprefix("$ nightcrew "))) == 2
    assert capsys.readouterr().err.splitlines() == [expected]


def test_a_target_pixel_beyond_the_cameras_chip_fails_check(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("acquisition.yaml").write_text(
        _block("yaml").replace("target_pixel: [400.0, 600.0]", "target_pixel: [400.0, 1600.0]"),
        encoding="utf-8",
    )
    Path("camera.yaml").write_text(
        "class: nightcrew.modules.sim.SimCamera\ndetector: {chip_width: 2048, chip_height: 1024}\n",
        encoding="utf-8",
    )
    assert main(["check", "."]) == 2
    assert capsys.readouterr().err.splitlines() == [
        "nightcrew: error: acquisition.yaml: key 'target_pixel': (400, 1600) is outside the 2048x1024 "
        "frame of the camera in camera.yaml"
    ]
