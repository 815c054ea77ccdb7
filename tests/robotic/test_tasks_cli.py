"""``nightcrew tasks``: exit codes and output, on a real SQLite file."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.robotic.samples import sample_paths
from tests.robotic.test_tasks_model import valid_group_data


def _sample(stem: str) -> str:
    return str(next(path for path in sample_paths() if path.stem == stem))


def test_add_list_show_cancel(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("NIGHTCREW_COMM", raising=False)
    db = str(tmp_path / "tasks.sqlite")
    assert main(["tasks", "--db", db, "add", _sample("double-cluster"), _sample("algol-light-curve")]) == 0
    out = capsys.readouterr().out
    assert "added 'Double cluster h and chi Persei' (group 1): tasks 1, 2" in out
    assert "added 'Algol light curve' (group 2): task 3" in out

    assert main(["tasks", "list", "--db", db]) == 0  # --db after the action works too
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == [
        "ID",
        "STATE",
        "NAME",
        "PROPOSAL",
        "PRIORITY",
        "DURATION",
        "WINDOWS",
        "CONFIGURATIONS",
    ]
    assert lines[1].startswith("1 ") and "PENDING" in lines[1] and "EXPOSE(NGC 869 (h Per))" in lines[1]
    assert "REPEAT_EXPOSE(Algol)" in lines[3] and "46m45s" in lines[3]  # 2700 s + overheads
    assert "2026-11-10 21:00 - 2026-11-11 01:00" in lines[3]

    assert main(["tasks", "--db", db, "cancel", "2", "--reason", "clouds all night"]) == 0
    assert capsys.readouterr().out.splitlines()[0] == "task 2 (Double cluster h and chi Persei): CANCELED"

    assert main(["tasks", "--db", db, "show", "2"]) == 0
    shown = capsys.readouterr().out
    assert "task 2: request 1 of group 1 'Double cluster h and chi Persei'" in shown
    assert "state: CANCELED (clouds all night)" in shown
    assert "done: configuration 0 series 1: 0/3 exposures" in shown
    assert "name: NGC 884 (chi Per)" in shown

    assert main(["tasks", "--db", db, "list", "--state", "canceled"]) == 0
    rows = capsys.readouterr().out.splitlines()[1:]
    assert [row.split()[0] for row in rows] == ["2"]


def test_an_invalid_file_stores_nothing_and_exits_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = valid_group_data()
    data["requests"][0]["configurations"][0]["instrument_configs"][1]["exposure_time"] = 0
    data["requests"][1]["windows"] = []
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    db = str(tmp_path / "tasks.sqlite")
    assert main(["tasks", "--db", db, "add", _sample("m15-globular-cluster"), str(bad)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.splitlines() == [
        f"nightcrew: error: {bad}: invalid request group:"
        " requests[0].configurations[0].instrument_configs[1].exposure_time: must be > 0; nothing was stored",
        f"nightcrew: error: {bad}: invalid request group:"
        " requests[1].windows: at least one window is needed (or a cadence); nothing was stored",
    ]
    assert main(["tasks", "--db", db, "list"]) == 0
    assert "(no tasks)" in capsys.readouterr().out


def test_unknown_tasks_and_refused_changes_exit_1(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("NIGHTCREW_TASKS_DB", str(tmp_path / "env.sqlite"))
    assert main(["tasks", "add", _sample("bias-and-darks")]) == 0
    assert (tmp_path / "env.sqlite").exists()
    capsys.readouterr()
    assert main(["tasks", "show", "42"]) == 1
    assert capsys.readouterr().err.strip() == f"nightcrew: error: no task '42' in {tmp_path / 'env.sqlite'}"
    assert main(["tasks", "cancel", "1"]) == 0
    assert main(["tasks", "cancel", "1"]) == 1
    assert "a CANCELED task cannot become CANCELED" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exited:
        main(["tasks", "list", "--state", "SLEEPING"])
    assert exited.value.code == 2
    assert "unknown state 'SLEEPING'" in capsys.readouterr().err
