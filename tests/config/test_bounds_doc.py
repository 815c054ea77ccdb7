"""docs/configuration.md "Bounds", as written: the bad file, its messages from check and run, the
table of other refusals, and a camera's refusal beyond its max_exposure_time."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.errors import InvalidArgumentError
from nightcrew.modules.sim import SimCamera
from nightcrew.testing import Observatory

REPO = Path(__file__).resolve().parents[2]
SECTION = (REPO / "docs" / "configuration.md").read_text().split("### Bounds", 1)[1].split("\n## ", 1)[0]


def test_the_bad_file_gets_the_documented_line_from_check_and_run(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    block = re.search(r"```yaml\n(# bad\.yaml\n.*?)```", SECTION, re.S)
    assert block is not None
    Path("bad.yaml").write_text(block[1])
    line = re.search(r"`nightcrew check bad.yaml` prints `([^`]+)`", SECTION)
    assert line is not None
    assert main(["check", "bad.yaml"]) == 2
    assert capsys.readouterr().err == line[1] + "\n"
    assert main(["run", "bad.yaml"]) == 2
    assert capsys.readouterr().err == f"nightcrew: error: {line[1]}\n"


def test_the_table_of_refusals_is_what_check_says(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    rows = re.findall(r"^\| `([a-z_]+: [^`]+)`(?: \(400 digits\))? \| `([^`]+)` \|$", SECTION, re.M)
    assert len(rows) == 3, rows
    for setting, message in rows:
        Path("x.yaml").write_text(
            f"class: nightcrew.modules.test.StandAlone\n{setting.replace('999…9', '9' * 400)}\n"
        )
        assert main(["check", "x.yaml"]) == 2
        assert capsys.readouterr().err == f"x.yaml:2: {message}\n"


async def test_a_camera_refuses_an_exposure_beyond_its_max_exposure_time_as_documented(
    observatory: Observatory,
) -> None:
    message = re.search(r"`(exposure_time 4000\.0 s is out of range[^`]+)`", SECTION)
    assert message is not None
    camera = await observatory.start(SimCamera, "camera", detector={"chip_width": 32, "chip_height": 32})
    with pytest.raises(InvalidArgumentError) as refused:
        await camera.set_exposure_time(4000.0)
    assert refused.value.message == message[1]
