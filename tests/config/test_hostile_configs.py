"""Seeded hostile module configurations: one clear error each, never a traceback, and ``nightcrew
check`` agrees with what ``nightcrew run`` makes of the same file.

The bundled example files are mutated line by line: a value is replaced by a number beyond physics
(10^400, 1e308, a 1e-320 interval, 2^70), a wrong type, a time zone that does not exist, broken
YAML, or a key is added with such a value. For every mutant, ``check`` exits 0 or 2 with one line
and no traceback, and ``run``'s loading (the same files, validated and built) succeeds exactly when
``check`` said OK, failing otherwise with a ConfigError.
"""

from __future__ import annotations

import logging
import random
import re
import shutil
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.cli.run import build_modules
from nightcrew.errors import NightcrewError

REPO = Path(__file__).resolve().parents[2]
EXAMPLES = REPO / "examples"
#: The examples mutated: every module file of the observatory and the stand-alone ones (the console,
#: ten times slower to build than the others, is left to its own tests).
BASES = sorted(
    [
        *EXAMPLES.glob("observatory/*.yaml"),
        *EXAMPLES.glob("observatory/robotic/*.yaml"),
        *EXAMPLES.glob("observatory/extras/*.yaml"),
        *EXAMPLES.glob("*.yaml"),
    ]
)
BASES = [path for path in BASES if path.name != "console.yaml"]

HOSTILE_VALUES = (
    "1e308",
    "-1e308",
    "1e3000",
    "9" * 400,
    "-" + "9" * 400,
    "9" * 400 + ".5",
    "1e-320",
    "-1e-320",
    ".nan",
    ".inf",
    "-.inf",
    str(2**70),
    str(-(2**70)),
    "0",
    "-1",
    "200",
    "-200",
    "Mars/Olympus",
    "''",
    '"' + "A" * 5000 + '"',
    "true",
    "null",
    "[]",
    "{}",
    "[1e308, .nan]",
    "{class: nightcrew.modules.test.StandAlone, interval: 1e-320}",
    "0x" + "f" * 40,
    "2026-13-45",
    "${NIGHTCREW_NO_SUCH_VARIABLE}",
    "*no_such_anchor",
    "!!python/object:os.system echo",
    "{",
)
#: Keys added with a hostile value (physical settings of many modules, and one nobody takes).
ADDED_KEYS = (
    "interval",
    "timezone",
    "park_alt",
    "max_exposure_time",
    "min_altitude",
    "poll_interval",
    "nosuch",
)
_SCALAR_LINE = re.compile(
    r"^(?P<lead>\s*(?:- )?[A-Za-z_][\w.-]*:[ \t]+)(?P<value>[^\s#][^#\n]*?)(?P<tail>\s*(?:#.*)?)$"
)


def mutate(text: str, rng: random.Random) -> str:
    """``text`` with one or two hostile changes."""
    lines = text.splitlines()
    for _ in range(rng.choice((1, 1, 2))):
        scalars = [i for i, line in enumerate(lines) if _SCALAR_LINE.match(line)]
        value = rng.choice(HOSTILE_VALUES)
        if scalars and rng.random() < 0.75:
            index = rng.choice(scalars)
            match = _SCALAR_LINE.match(lines[index])
            assert match is not None
            lines[index] = f"{match['lead']}{value}{match['tail']}"
        else:
            lines.append(f"{rng.choice(ADDED_KEYS)}: {value}")
    return "\n".join(lines) + "\n"


def _copy_examples(tmp_path: Path) -> dict[Path, Path]:
    """The bases copied under ``tmp_path`` (their includes beside them), original → copy."""
    shutil.copytree(EXAMPLES / "observatory", tmp_path / "observatory")
    for path in EXAMPLES.glob("*.yaml"):
        shutil.copy(path, tmp_path / path.name)
    return {path: tmp_path / path.relative_to(EXAMPLES) for path in BASES}


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_mutated_configs_give_one_clear_error_and_check_agrees_with_run(
    seed: int,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    caplog: pytest.LogCaptureFixture,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    caplog.set_level(logging.WARNING)
    monkeypatch.chdir(tmp_path)
    copies = _copy_examples(tmp_path)
    rng = random.Random(seed)
    verdicts = {"OK": 0, "refused": 0}
    for number in range(80):
        base = copies[rng.choice(BASES)]
        mutant = base.with_name(f"mutant{number}.yaml")
        mutant.write_text(mutate(base.read_text(), rng))
        shown = mutant.read_text()[:2000]

        code = main(["check", str(mutant)])
        out, err = capsys.readouterr()
        assert code in (0, 2), shown
        assert "Traceback" not in out + err, err
        assert len(err.splitlines()) == (0 if code == 0 else 1), err

        try:
            build_modules([str(mutant)])
            run_ok = True
        except NightcrewError:
            run_ok = False
        assert run_ok == (code == 0), (
            f"check said {code}, run {'built it' if run_ok else 'refused'}:\n{shown}"
        )
        verdicts["OK" if run_ok else "refused"] += 1
    assert not [r for r in caplog.records if r.exc_info], "a traceback was logged"
    print(f"seed {seed}: 80 mutated configs, {verdicts}")
    assert verdicts["refused"] >= 40, verdicts  # the mutations are hostile enough to mean something
