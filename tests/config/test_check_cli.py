"""``nightcrew check``: one line per file, exit 0 when all are valid, 2 otherwise, no traceback."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from tests.config.conftest import WriteFiles

S = "tests.config.sample_classes"
VALID = f"class: {S}.Leaf\nmessage: hello\ninterval: ${{INTERVAL:-10}}\n"
INVALID = f"class: {S}.Leaf\nmessage: hello\nintervall: 5\n"
REPO = Path(__file__).resolve().parents[2]


def test_valid_file(write: WriteFiles, capsys: pytest.CaptureFixture[str]) -> None:
    write({"leaf.yaml": VALID})
    assert main(["check", "leaf.yaml"]) == 0
    captured = capsys.readouterr()
    assert captured.out == "OK leaf.yaml\n"
    assert captured.err == ""


def test_invalid_file_gives_one_line(write: WriteFiles, capsys: pytest.CaptureFixture[str]) -> None:
    write({"leaf.yaml": INVALID})
    assert main(["check", "leaf.yaml"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err == (
        f"leaf.yaml:3: key 'intervall': unknown key 'intervall' for {S}.Leaf (did you mean 'interval'?)\n"
    )


def test_every_file_is_reported(write: WriteFiles, capsys: pytest.CaptureFixture[str]) -> None:
    write({"good.yaml": VALID, "bad.yaml": INVALID, "broken.yaml": "class: [\n"})
    assert main(["check", "good.yaml", "bad.yaml", "broken.yaml", "missing.yaml"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "OK good.yaml\n"
    errors = captured.err.splitlines()
    assert len(errors) == 3
    assert errors[0].startswith("bad.yaml:3: key 'intervall'")
    assert errors[1].startswith("broken.yaml:2: invalid YAML")
    assert errors[2] == "missing.yaml: file not found"


def test_error_in_included_file_names_the_checked_file(
    write: WriteFiles, capsys: pytest.CaptureFixture[str]
) -> None:
    write({"leaf.yaml": f"class: {S}.Leaf\n<<: !include base.yaml\n", "base.yaml": "message: 5\n"})
    assert main(["check", "leaf.yaml"]) == 2
    assert capsys.readouterr().err == (
        "base.yaml:1: key 'message': expected str, got int 5 (included from leaf.yaml)\n"
    )


def test_directory_recursive_without_fragments(write: WriteFiles, capsys: pytest.CaptureFixture[str]) -> None:
    write(
        {
            "conf/leaf.yaml": f"class: {S}.Leaf\n<<: !include common/base.yaml\n",
            "conf/common/base.yaml": "message: shared\n",  # a fragment: checked through leaf.yaml
            "conf/sim/other.yml": VALID,
            "conf/.hidden/ignored.yaml": INVALID,
            "conf/notes.txt": "not a config",
        }
    )
    assert main(["check", "conf"]) == 0
    assert capsys.readouterr().out == "OK conf/leaf.yaml\nOK conf/sim/other.yml\n"


def test_directory_with_an_invalid_file(write: WriteFiles, capsys: pytest.CaptureFixture[str]) -> None:
    write({"conf/a.yaml": VALID, "conf/b.yaml": INVALID})
    assert main(["check", "conf/"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "OK conf/a.yaml\n"
    assert captured.err.count("\n") == 1 and captured.err.startswith("conf/b.yaml:3:")


def test_empty_directory(write: WriteFiles, capsys: pytest.CaptureFixture[str]) -> None:
    write({"conf/notes.txt": ""})
    assert main(["check", "conf"]) == 2
    assert capsys.readouterr().err == "nightcrew: error: no *.yaml files in conf\n"


def test_debug_shows_the_traceback(write: WriteFiles) -> None:
    write({"leaf.yaml": INVALID})
    with pytest.raises(Exception, match="unknown key 'intervall'"):
        main(["--debug", "check", "leaf.yaml"])


def run_command(args: list[str], cwd: Path) -> subprocess.CompletedProcess[str]:
    # The sample classes live in the tests package, importable from the repository root.
    environ = {**os.environ, "PYTHONPATH": str(REPO)}
    environ.pop("INTERVAL", None)
    return subprocess.run(args, cwd=cwd, env=environ, capture_output=True, text=True, timeout=60, check=False)


@pytest.mark.parametrize(
    "command",
    [[sys.executable, "-m", "nightcrew"], [str(Path(sys.executable).parent / "nightcrew")]],
    ids=["python -m nightcrew", "nightcrew script"],
)
def test_as_a_subprocess(command: list[str], write: WriteFiles, tmp_path: Path) -> None:
    if not Path(command[0]).exists():
        pytest.skip("no nightcrew script next to this Python")
    write({"good.yaml": VALID, "bad.yaml": INVALID})
    result = run_command([*command, "check", "good.yaml"], tmp_path)
    assert (result.returncode, result.stdout, result.stderr) == (0, "OK good.yaml\n", "")
    result = run_command([*command, "check", "bad.yaml"], tmp_path)
    assert result.returncode == 2
    assert result.stdout == ""
    assert len(result.stderr.splitlines()) == 1
    assert "Traceback" not in result.stderr
    assert result.stderr.startswith("bad.yaml:3: key 'intervall': unknown key 'intervall'")
