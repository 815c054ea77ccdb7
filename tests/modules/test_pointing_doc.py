"""docs/mounts.md, "Pointing model": its files pass ``nightcrew check`` as written, its command fits a
series' CSV, and a model file for another mount gives the error line it shows."""

from __future__ import annotations

import csv
import re
import shlex
from pathlib import Path

import numpy as np
import pytest
import yaml

from nightcrew.astro.pointing import PointingModel, from_hadec, to_hadec
from nightcrew.cli.main import main
from nightcrew.modules.pointing.series import CSV_COLUMNS, pointing_row

DOC = (Path(__file__).parents[2] / "docs/mounts.md").read_text(encoding="utf-8")
SECTION = DOC.split("## Pointing model", 1)[1]


def block(language: str, first_line: str) -> str:
    """The ``language`` block of the section whose first line is ``first_line``."""
    for text in re.findall(rf"^```{language}\n(.*?)^```", SECTION, flags=re.M | re.S):
        if text.startswith(first_line):
            return str(text)
    raise AssertionError(f"no {language} block starting {first_line!r} in the pointing model section")


def gem_telescope() -> str:
    """The simulated GEM of the same document, with the model and the documented injected terms."""
    gem = str(re.findall(r"^```yaml\n(.*?)^```", DOC, flags=re.M | re.S)[0])
    return gem + "pointing_model: pointing-model.yaml\n" + block("yaml", "pointing_terms:")


def write_series(path: Path, count: int = 40) -> None:
    """A series' CSV of a mount with the documented model's terms (1" solve noise)."""
    latitude, longitude, when = 51.56, 9.94, 1_768_514_400.0
    truth = PointingModel("telescope", latitude, {"IH": 1500.0, "ID": -1100.0, "MA": 900.0, "ME": -800.0})
    rng = np.random.default_rng(2)
    rows = []
    for _ in range(count):
        ha, dec = rng.uniform(-80.0, 80.0), rng.uniform(-10.0, 80.0)
        commanded = from_hadec(ha, dec, longitude, when)
        true_ha, true_dec = truth.to_sky(*to_hadec(*commanded, longitude, when))
        solved = from_hadec(true_ha, true_dec + rng.normal(0.0, 1.0 / 3600.0), longitude, when)
        row = pointing_row("2026-01-15T22:00:00.000Z", (45.0, 180.0), commanded, solved, (45.0, 180.0))
        rows.append(row.csv() | {"latitude": latitude, "longitude": longitude})
    with path.open("w", newline="", encoding="utf-8") as stream:
        writer = csv.DictWriter(stream, fieldnames=CSV_COLUMNS)
        writer.writeheader()
        writer.writerows(rows)


def test_the_documented_command_fits_the_model_and_the_files_pass_check(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    command = block("console", "$ nightcrew pointing fit").splitlines()[0]
    csv_name = shlex.split(command)[4]
    write_series(tmp_path / csv_name)
    assert main(shlex.split(command.removeprefix("$ nightcrew "))) == 0
    printed = capsys.readouterr().out
    assert re.search(r"^IH +1[45]\d\d\.\d\d +\d+\.\d\d$", printed, flags=re.M), printed
    assert "RMS before" in printed
    model = PointingModel.from_dict(yaml.safe_load(Path("pointing-model.yaml").read_text()))
    assert model.mount == "telescope" and model.statistics is not None and model.statistics.rms_after < 5.0

    for name, text in [
        ("telescope.yaml", gem_telescope()),
        ("pointing.yaml", block("yaml", "# pointing.yaml")),
        ("refit.yaml", block("yaml", "# refit.yaml")),
    ]:
        Path(name).write_text(text, encoding="utf-8")
        assert main(["check", name]) == 0, capsys.readouterr().err


def test_a_model_for_another_mount_gives_the_documented_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("telescope.yaml").write_text(gem_telescope(), encoding="utf-8")
    documented = block("yaml", "# pointing-model.yaml")
    Path("pointing-model.yaml").write_text(documented, encoding="utf-8")
    assert main(["check", "telescope.yaml"]) == 0, capsys.readouterr().err
    capsys.readouterr()

    command, expected = block("console", "$ nightcrew check").splitlines()[:2]
    other = re.search(r"is for mount '(\w+)'", expected)
    assert other is not None
    Path("pointing-model.yaml").write_text(documented.replace("mount: telescope", f"mount: {other.group(1)}"))
    assert main(shlex.split(command.removeprefix("$ nightcrew "))) == 2
    err = capsys.readouterr().err.splitlines()
    assert [line.replace(str(tmp_path) + "/", "") for line in err] == [expected]
