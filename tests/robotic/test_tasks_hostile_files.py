"""Seeded malformed task files: one clear error each, never a traceback, nothing stored that cannot
be read back; and a task stored before a bound existed is listed as unreadable, not a crash.

The bundled sample request groups are mutated value by value (numbers beyond physics such as an
exposure of 1e308 s or a 400-digit count, wrong types, impossible dates, broken YAML). For every
mutant ``nightcrew tasks add`` exits 0 or 2 without a traceback, agrees with ``nightcrew check``,
and a refused file leaves the database as it was; at the end ``tasks list`` reads every row.
"""

from __future__ import annotations

import json
import random
import re
import sqlite3
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.robotic.samples import sample_paths

HOSTILE_VALUES = (
    "1e308",
    "-1e308",
    "1e3000",
    "9" * 400,
    "9" * 400 + ".5",
    "1e-320",
    ".nan",
    ".inf",
    str(2**70),
    "0",
    "-1",
    "200",
    "100001",
    "''",
    '"' + "B" * 3000 + '"',
    "true",
    "null",
    "[]",
    "{}",
    "2026-13-45T25:00:00Z",
    "0001-01-01T00:00:00Z",
    "9999-12-31T23:59:59Z",
    "*no_such_anchor",
    "{",
)
#: ``key: value`` in block or flow style; the value ends at a comma, a brace, a comment or the line.
_KEY_VALUE = re.compile(
    r"(?P<lead>\b[A-Za-z_]\w*:[ \t]+)(?P<value>[^\s,{}\[\]#][^,{}\[\]#\n]*?)(?=\s*(?:[,}\]#]|$))", re.M
)


def mutate(text: str, rng: random.Random) -> str:
    """``text`` with one to three values replaced by hostile ones."""
    for _ in range(rng.choice((1, 1, 2, 3))):
        matches = list(_KEY_VALUE.finditer(text))
        match = rng.choice(matches)
        text = text[: match.start("value")] + rng.choice(HOSTILE_VALUES) + text[match.end("value") :]
    return text


def _stored(db: Path) -> int:
    if not db.exists():
        return 0
    with sqlite3.connect(db) as conn:
        return int(conn.execute("SELECT COUNT(*) FROM tasks").fetchone()[0])


@pytest.mark.parametrize("seed", [11, 12])
def test_malformed_task_files_are_refused_whole_and_everything_stored_reads_back(
    seed: int, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("NIGHTCREW_COMM", raising=False)
    db = tmp_path / "tasks.sqlite"
    samples = sorted(sample_paths())
    rng = random.Random(seed)
    refused = added = 0
    for number in range(60):
        mutant = tmp_path / f"mutant{number}.yaml"
        mutant.write_text(mutate(rng.choice(samples).read_text(), rng))
        shown = mutant.read_text()[:1500]
        before = _stored(db)

        checked = main(["check", str(mutant)])
        code = main(["tasks", "--db", str(db), "add", str(mutant)])
        out, err = capsys.readouterr()
        assert "Traceback" not in out + err, err
        assert code in (0, 2), shown
        assert (checked == 0) == (code == 0), f"check said {checked}, tasks add {code}:\n{shown}"
        if code == 2:
            refused += 1
            assert _stored(db) == before, f"a refused file stored something:\n{shown}"
            assert "nothing was stored" in err or "invalid" in err, err
        else:
            added += 1
    assert main(["tasks", "--db", str(db), "list"]) == 0
    out, err = capsys.readouterr()
    assert "UNREADABLE" not in out and "Traceback" not in err
    print(f"seed {seed}: 60 mutated task files, {refused} refused, {added} added")
    assert refused >= 40, (refused, added)


def test_a_task_stored_before_a_bound_existed_is_listed_as_unreadable(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.delenv("NIGHTCREW_COMM", raising=False)
    db = tmp_path / "tasks.sqlite"
    sample = next(path for path in sample_paths() if path.stem == "bias-and-darks")
    assert main(["tasks", "--db", str(db), "add", str(sample)]) == 0
    # What an older release let through: a dark of 1e308 s.
    with sqlite3.connect(db) as conn:
        request = json.loads(conn.execute("SELECT request FROM tasks WHERE id = 1").fetchone()[0])
        request["configurations"][-1]["instrument_configs"][0]["exposure_time"] = 1e308
        conn.execute("UPDATE tasks SET request = ? WHERE id = 1", (json.dumps(request),))
    capsys.readouterr()

    assert main(["tasks", "--db", str(db), "list"]) == 0
    rows = capsys.readouterr().out.splitlines()
    unreadable = [row for row in rows if row.split()[:2] == ["1", "UNREADABLE"]]
    assert len(unreadable) == 1, rows
    assert "exposure_time: must be <= 86400" in unreadable[0]

    assert main(["tasks", "--db", str(db), "show", "1"]) == 1
    assert (
        capsys.readouterr()
        .err.strip()
        .endswith(f"task 1 in {db} cannot be read: {unreadable[0].split('  ')[-1].strip()}")
    )
