"""Hostile configuration and task files: one clear error each, never a traceback or a hang.

The generators are seeded: the same run mutates the same files the same way. "check and run agree"
is tested on every mutated file: ``nightcrew check`` (check_file) and ``nightcrew run``'s build
(build_modules) must both accept it or both refuse it with a ConfigError.
"""

from __future__ import annotations

import random
import shutil
from pathlib import Path

import pytest

from nightcrew.cli.check import check_file
from nightcrew.cli.main import main
from nightcrew.cli.run import build_modules
from nightcrew.errors import ConfigError
from nightcrew.night.build import bundled_observatory
from nightcrew.server import create_missing_passwords

OBSERVATORY = bundled_observatory()
MUTATED_FILES = (
    "camera.yaml",
    "roof.yaml",
    "telescope.yaml",
    "conditions.yaml",
    "focuser.yaml",
    "filters.yaml",
)

ALIAS_BOMB = "".join(
    f"{name}: &{name} [{', '.join([f'*{prev}'] * 10) if prev else ', '.join(['lol'] * 10)}]\n"
    for prev, name in zip(["", "a", "b", "c", "d", "e", "f", "g", "h"], "abcdefghi", strict=True)
)
HOSTILE_VALUES = [
    ".nan",
    ".inf",
    "-.inf",
    "-1",
    "0",
    "1e400",
    "-1e400",
    "99999999999999999999999999",
    '""',
    "null",
    "true",
    "[1, 2, 3]",
    "{a: 1}",
    "*nowhere",
    "!!python/object/apply:os.system [echo]",
    "2026-02-30",
    "2026-13-01T25:61:00",
    "${NIGHTCREW_UNSET_VARIABLE}",
    "${",
    "!include /nonexistent.yaml",
    "[" * 200 + "]" * 200,
    "'" + "x" * 5000 + "'",
    "!!binary AAAA",
    "0x7fffffffffffffffffff",
    "~",
]


def _verdict(action: object, path: Path) -> str:
    """'ok' or 'refused'; anything but a ConfigError fails the test (that is a traceback)."""
    try:
        action(path)  # type: ignore[operator]
    except ConfigError:
        return "refused"
    return "ok"


def _mutate(text: str, rng: random.Random) -> bytes:
    lines = text.splitlines()
    kind = rng.randrange(10)
    valued = [i for i, line in enumerate(lines) if ":" in line and not line.lstrip().startswith("#")]
    if kind < 6 and valued:  # one value replaced by a hostile one
        i = rng.choice(valued)
        key, _, _ = lines[i].partition(":")
        lines[i] = f"{key}: {rng.choice(HOSTILE_VALUES)}"
    elif kind == 6:
        lines.append(ALIAS_BOMB.rstrip("\n"))
    elif kind == 7:  # a random cut
        cut = rng.randrange(len(text))
        return text[:cut].encode()
    elif kind == 8:  # bytes that are not UTF-8
        data = bytearray(text.encode())
        data.insert(rng.randrange(len(data)), rng.choice([0xFF, 0xC3, 0x80, 0xFE]))
        return bytes(data)
    elif valued:  # duplicate a key line
        i = rng.choice(valued)
        lines.insert(i, lines[i])
    return ("\n".join(lines) + "\n").encode()


def test_mutated_configs_check_and_run_agree(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    shutil.copytree(OBSERVATORY, tmp_path / "obs")
    monkeypatch.chdir(tmp_path / "obs")
    # What the files' comm needs: the passwords `server init` makes (secrets/) and its certificate.
    (tmp_path / "ca.crt").write_text("a certificate\n")
    monkeypatch.delenv("SIM_XMPP_SECRETS", raising=False)
    create_missing_passwords(Path(".").glob("*.yaml"))
    monkeypatch.setenv("SIM_XMPP_CA_FILE", str(tmp_path / "ca.crt"))
    rng = random.Random(20261124)
    originals = {name: Path(name).read_text() for name in MUTATED_FILES}
    verdicts = {"ok": 0, "refused": 0}
    for round_ in range(300):
        name = MUTATED_FILES[round_ % len(MUTATED_FILES)]
        path = Path(f"mutated-{round_}.yaml")
        path.write_bytes(_mutate(originals[name], rng))
        checked = _verdict(check_file, path)
        ran = _verdict(lambda p: build_modules([str(p)]), path)
        assert checked == ran, f"check said {checked}, run {ran} for {path}:\n{path.read_text('latin-1')}"
        verdicts[checked] += 1
        path.unlink()
    # The generator really produced both kinds (a generator that only breaks files proves little).
    assert verdicts["refused"] > 100 and verdicts["ok"] > 10, verdicts


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (ALIAS_BOMB, "aliases expand to more than"),
        ("class: x.Y\nvalue: " + "[" * 600 + "]" * 600 + "\n", "nested deeper than"),
        ("class: x.Y\nvalue: " + "{a: " * 600 + "1" + "}" * 600 + "\n", "nested deeper than"),
        ("class: x.Y\nwhen: 2026-02-30\n", "day is out of range"),
        ("class: x.Y\nvalue: [&a [*a]]\n", "recursive alias"),
    ],
)
def test_hostile_yaml_gets_one_line(
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
    text: str,
    message: str,
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("bad.yaml").write_text(text)
    assert main(["check", "bad.yaml"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.count("\n") == 1 and captured.err.startswith("bad.yaml:")
    assert message in captured.err


def test_oversized_and_non_utf8_files(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("huge.yaml").write_text("class: x.Y\n" + "# padding\n" * 200_000)
    Path("latin.yaml").write_bytes(b"class: x.Y\nname: caf\xe9\n")
    assert main(["check", "huge.yaml", "latin.yaml"]) == 2
    assert capsys.readouterr().err.splitlines() == [
        "huge.yaml: file larger than 1000000 bytes",
        "latin.yaml:2: not UTF-8 text (byte 0xe9)",
    ]


@pytest.mark.parametrize("value", [".nan", ".inf", "-.inf", "1e999"])
def test_non_finite_float_setting_refused_by_check_and_run(tmp_path: Path, value: str) -> None:
    path = tmp_path / "roof.yaml"
    path.write_text(f"class: nightcrew.modules.sim.SimRoof\nopen_time: {value}\n")
    for action in (check_file, lambda p: build_modules([str(p)])):
        with pytest.raises(ConfigError, match="key 'open_time': expected a finite number"):
            action(path)


def test_constructor_checks_are_part_of_check(tmp_path: Path) -> None:
    # A value of the right type that the constructor refuses: check must refuse it as run does.
    path = tmp_path / "roof.yaml"
    path.write_text("class: nightcrew.modules.sim.SimRoof\nopen_time: -5\n")
    with pytest.raises(ConfigError) as checked:
        check_file(path)
    with pytest.raises(ConfigError) as ran:
        build_modules([str(path)])
    assert str(checked.value) == str(ran.value)


def test_numeric_password_is_never_printed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("cam.yaml").write_text(
        "class: nightcrew.modules.test.StandAlone\n"
        "comm: {class: nightcrew.comm.xmpp.XmppComm, jid: cam@obs.test, password: 73914825}\n"
    )
    assert main(["check", "cam.yaml"]) == 2
    captured = capsys.readouterr()
    assert "73914825" not in captured.err + captured.out
    assert "key 'comm.password': expected str, got int (value not shown)" in captured.err
