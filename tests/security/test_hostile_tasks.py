"""``nightcrew tasks add`` with hostile files: a clear message per bad file, nothing stored, no traceback."""

from __future__ import annotations

import contextlib
import json
import random
from pathlib import Path

import pytest
import yaml

from nightcrew.cli.main import main
from nightcrew.robotic.samples import sample_paths

HOSTILE_VALUES = [
    ".inf",
    "-.inf",
    ".nan",
    "1e999",
    "-1",
    "0",
    "2026-02-30T25:00:00",
    "2026-13-45",
    "null",
    "[]",
    "{}",
    "[" * 300 + "]" * 300,
    "*nowhere",
    "!!python/object/apply:os.system [echo]",
    "'" + "x" * 3000 + "'",
    "true",
    "99999999999999999999999999999",
]


def _count_tasks(db: Path, capsys: pytest.CaptureFixture[str]) -> int:
    assert main(["tasks", "--db", str(db), "list"]) == 0
    return sum(1 for line in capsys.readouterr().out.splitlines()[1:] if line and line != "(no tasks)")


@pytest.mark.parametrize(
    ("name", "data", "message"),
    [
        ("latin.yaml", b"name: caf\xe9\n", "not UTF-8 text"),
        ("date.yaml", b"name: x\nwindows: [{start: 2026-02-30, end: 2026-03-01}]\n", "day is out of range"),
        ("deep.yaml", b"name: " + b"[" * 1000 + b"]" * 1000 + b"\n", "nested deeper than"),
        ("deep.json", b'{"name": ' + b"[" * 100000 + b"]" * 100000 + b"}", "nested deeper than"),
        ("nan.json", b'{"name": "x", "priority": NaN}', "NaN is not a number JSON allows"),
    ],
)
def test_bad_file_one_message_nothing_stored(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], name: str, data: bytes, message: str
) -> None:
    path = tmp_path / name
    path.write_bytes(data)
    db = tmp_path / "tasks.sqlite"
    assert main(["tasks", "--db", str(db), "add", str(sample_paths()[0]), str(path)]) == 2
    err = capsys.readouterr().err
    assert message in err and f"{path}: invalid request group" in err
    assert err.rstrip().endswith("nothing was stored")
    assert _count_tasks(db, capsys) == 0


def test_infinite_priority_is_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = sample_paths()[0].read_text()
    path = tmp_path / "inf.yaml"
    path.write_text(
        text.replace("priority:", "priority: .inf #", 1) if "priority:" in text else text + "ipp: .inf\n"
    )
    db = tmp_path / "tasks.sqlite"
    assert main(["tasks", "--db", str(db), "add", str(path)]) == 2
    assert "finite" in capsys.readouterr().err
    assert _count_tasks(db, capsys) == 0


def test_mutated_task_files(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Hundreds of mutated sample files: each is stored or refused with a message; never a traceback."""
    rng = random.Random(17)
    samples = [path.read_text() for path in sample_paths()]
    db = tmp_path / "tasks.sqlite"
    outcomes = {0: 0, 2: 0}
    stored = 0
    for round_ in range(200):
        lines = rng.choice(samples).splitlines()
        valued = [i for i, line in enumerate(lines) if ": " in line and not line.lstrip().startswith("#")]
        for _ in range(rng.randint(1, 3)):
            i = rng.choice(valued)
            key = lines[i].partition(": ")[0]
            lines[i] = f"{key}: {rng.choice(HOSTILE_VALUES)}"
        data = ("\n".join(lines) + "\n").encode()
        if round_ % 10 == 0:
            data = data[: rng.randrange(len(data))] + b"\xff"
        path = tmp_path / f"task-{round_}.{'json' if round_ % 7 == 0 else 'yaml'}"
        if round_ % 7 == 0:  # the same document as JSON, where it parses as YAML
            # A document that does not even parse as YAML stays as is: not JSON, refused cleanly.
            with contextlib.suppress(yaml.YAMLError, UnicodeDecodeError, RecursionError, ValueError):
                data = json.dumps(yaml.safe_load(data.decode("utf-8")), default=str).encode()
        path.write_bytes(data)
        code = main(["tasks", "--db", str(db), "add", str(path)])
        err = capsys.readouterr().err
        assert code in outcomes, err
        outcomes[code] += 1
        if code == 2:
            assert f"{path}: invalid request group" in err and "nothing was stored" in err
            assert "Traceback" not in err
        else:
            stored += 1
    assert outcomes[2] > 100, outcomes
    assert _count_tasks(db, capsys) >= stored
