"""systemd units, log formats and the restart policy (no server needed)."""

from __future__ import annotations

import json
import logging
import subprocess
import sys
import time
from pathlib import Path

import pytest

from nightcrew.supervisor import DEFAULT_STOP_TIMEOUT, RestartPolicy, configure_logging, systemd_units
from nightcrew.supervisor._logging import JsonLinesFormatter, SystemdFormatter

from .conftest import REPOSITORY


def write_modules(directory: Path) -> None:
    (directory / "common.yaml").write_text("class: nightcrew.clock.RealClock\n")
    (directory / "roof.yaml").write_text(
        "class: nightcrew.modules.test.StandAlone\nclock: !include common.yaml\n"
    )
    (directory / "camera.yaml").write_text("class: nightcrew.modules.test.StandAlone\n")
    (directory / "clock.yaml").write_text("class: nightcrew.clock.RealClock\n")  # not a module


def test_one_supervisor_unit(tmp_path: Path) -> None:
    write_modules(tmp_path)
    units = systemd_units(tmp_path)
    assert list(units) == ["nightcrew.service"]
    text = units["nightcrew.service"]
    assert f"ExecStart={sys.executable} -m nightcrew --log-format systemd up {tmp_path} " in text
    assert "Restart=on-failure" in text and f"WorkingDirectory={tmp_path}" in text
    # systemd must not kill the supervisor while a module parks or closes within its stop timeout
    stop_sec = float(
        next(line for line in text.splitlines() if line.startswith("TimeoutStopSec=")).split("=")[1]
    )
    assert stop_sec >= 2 * DEFAULT_STOP_TIMEOUT  # the mount's park and the roof's close, one after the other


def test_one_unit_per_module(tmp_path: Path) -> None:
    write_modules(tmp_path)
    units = systemd_units(tmp_path, per_module=True, environment_file=tmp_path / "secrets.env")
    assert sorted(units) == ["nightcrew-camera.service", "nightcrew-roof.service"]
    assert f"run {tmp_path / 'roof.yaml'}\n" in units["nightcrew-roof.service"]
    assert f"EnvironmentFile={tmp_path / 'secrets.env'}\n" in units["nightcrew-roof.service"]


def test_systemd_command_writes_the_units(tmp_path: Path) -> None:
    write_modules(tmp_path)
    out = tmp_path / "units"
    done = subprocess.run(
        [sys.executable, "-m", "nightcrew", "systemd", str(tmp_path), "--out", str(out), "--per-module"],
        capture_output=True, text=True, timeout=60, cwd=REPOSITORY,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert sorted(p.name for p in out.iterdir()) == ["nightcrew-camera.service", "nightcrew-roof.service"]


def record(level: int, message: str) -> logging.LogRecord:
    return logging.LogRecord("nightcrew.test", level, __file__, 1, message, None, None)


def test_json_lines_and_journald_prefixes() -> None:
    entry = json.loads(JsonLinesFormatter().format(record(logging.WARNING, "roof closing")))
    assert (entry["level"], entry["logger"], entry["message"]) == (
        "WARNING",
        "nightcrew.test",
        "roof closing",
    )
    assert entry["time"].endswith("+00:00")
    systemd = SystemdFormatter()
    assert systemd.format(record(logging.ERROR, "a\nb")) == "<3>nightcrew.test: a\n<3>b"
    assert systemd.format(record(logging.INFO, "ok")) == "<6>nightcrew.test: ok"
    assert systemd.format(record(logging.DEBUG, "x")) == "<7>nightcrew.test: x"


def test_rotating_json_log_file_of_a_module(tmp_path: Path) -> None:
    config = tmp_path / "hello.yaml"
    config.write_text("class: nightcrew.modules.test.StandAlone\nmessage: hello file\ninterval: 0.01\n")
    log = tmp_path / "logs" / "hello.log"
    process = subprocess.Popen(
        [sys.executable, "-m", "nightcrew", "--log-file", str(log), "--log-file-format", "json",
         "run", str(config)],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPOSITORY,
    )  # fmt: skip
    try:
        deadline = time.monotonic() + 60
        while not (log.exists() and log.read_text().count("hello file") >= 3):
            assert process.poll() is None and time.monotonic() < deadline, "no three lines in the log file"
            time.sleep(0.05)
    finally:
        process.terminate()
        process.wait(timeout=30)
    lines = [json.loads(line) for line in log.read_text().splitlines()]
    hello = [line for line in lines if line["message"] == "hello file"]
    assert len(hello) >= 3 and hello[0]["module"] == "hello" and hello[0]["level"] == "INFO"


def test_restart_policy_backoff_and_limit() -> None:
    policy = RestartPolicy(first_delay=1, max_delay=4, stable_after=30, max_restarts=4, window=100)
    assert [policy.after_exit(0, 1), policy.after_exit(2, 3), policy.after_exit(6, 7)] == [1, 2, 4]
    assert policy.after_exit(11, 12) == 4  # capped
    assert policy.after_exit(16, 17) is None  # 4 restarts within 100 s: give up
    policy.reset()
    assert policy.after_exit(100, 200) == 1  # ran long: healthy again
    with pytest.raises(ValueError, match="first_delay <= max_delay"):
        RestartPolicy(first_delay=5, max_delay=1)


def test_configure_logging_twice_keeps_one_file_handler(tmp_path: Path) -> None:
    root = logging.getLogger()
    before = list(root.handlers)
    try:
        configure_logging(logging.INFO, log_file=tmp_path / "a.log")
        configure_logging(logging.INFO, log_file=tmp_path / "b.log")
        added = [h for h in root.handlers if h not in before]
        assert len(added) == 1 and Path(getattr(added[0], "baseFilename", "")) == tmp_path / "b.log"
    finally:
        configure_logging(logging.INFO)  # removes what it added
    assert root.handlers == before


def test_module_files_lists_modules_and_broken_files_skips_others(tmp_path: Path) -> None:
    from nightcrew.supervisor import module_files

    write_modules(tmp_path)
    (tmp_path / "typo.yaml").write_text("class: nightcrew.modules.test.StandAlonee\n")
    (tmp_path / "secret.yaml").write_text(
        "class: nightcrew.modules.test.StandAlone\nmessage: ${NO_SUCH_VAR_H1}\n"
    )
    (tmp_path / "options").mkdir()  # module files added on request (nightcrew sim --console): not started
    (tmp_path / "options" / "console.yaml").write_text("class: nightcrew.modules.test.StandAlone\n")
    found = {m.name: m for m in module_files(tmp_path)}
    assert sorted(found) == [
        "camera",
        "roof",
        "secret",
        "typo",
    ]  # clock.yaml: not a module; common.yaml: included
    assert found["roof"].error is None and found["camera"].error is None
    assert found["typo"].error is not None and "StandAlonee" in found["typo"].error
    assert found["secret"].error is not None and "NO_SUCH_VAR_H1" in found["secret"].error


def test_up_on_a_directory_without_modules_is_one_clear_error(tmp_path: Path) -> None:
    (tmp_path / "clock.yaml").write_text("class: nightcrew.clock.RealClock\n")
    done = subprocess.run(
        [sys.executable, "-m", "nightcrew", "up", str(tmp_path), "--socket", str(tmp_path / "s")],
        capture_output=True, text=True, timeout=60, cwd=REPOSITORY,
    )  # fmt: skip
    assert done.returncode == 2
    assert done.stderr.splitlines()[-1] == f"nightcrew: error: no module configurations in {tmp_path}"
