"""The bundled observatory as processes, robotic tasks end to end, started as docs/observatory.md says.

``nightcrew check``, ``nightcrew server init`` and ``server start`` (Prosody), ``nightcrew up
examples/observatory`` (every module of the bundled observatory, devices and robotic, each a process
on the shared accelerated clock, as its files name them), ``nightcrew tasks add``: the task is
observed, its frames are written and it ends COMPLETED. Only commands; no Python of the test's own
talks to the modules.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest

from .conftest import REPOSITORY

pytestmark = [pytest.mark.xmpp, pytest.mark.timeout(900)]
OBSERVATORY = REPOSITORY / "examples" / "observatory"
#: M39, high in the north-east at dusk of the default night; two short frames.
TASK = """\
name: M39 from the command line
proposal: up-test
priority: 1
requests:
  - location: {telescope_class: 0m4}
    windows:
      - {start: 2026-11-10T17:50:00Z, end: 2026-11-11T05:00:00Z}
    configurations:
      - type: EXPOSE
        target: {name: M39, ra: 322.95, dec: 48.43}
        instrument_configs:
          - {exposure_time: 10, exposure_count: 2, optical_elements: {filter: V}}
"""
#: Clock seconds per wall second: the weather must stay good 900 clock s before the roof opens.
SPEED = "30"
#: Wall seconds the task may take from start-up (20 processes start on a busy machine first).
TASK_TIMEOUT = 600.0


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def nightcrew(*args: str, env: dict[str, str], cwd: Path) -> str:
    result = subprocess.run(
        [sys.executable, "-m", "nightcrew", *args],
        env=env,
        cwd=cwd,
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == 0, f"nightcrew {' '.join(args)}: {result.stdout}{result.stderr}"
    return result.stdout


@pytest.fixture
def environment(tmp_path: Path) -> Iterator[dict[str, str]]:
    """The variables of docs/observatory.md, pointing into ``tmp_path``; Prosody set up
    and started with ``nightcrew server``, stopped after."""
    if shutil.which("prosody") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("prosody is not installed")
        pytest.skip("prosody is not installed")
    port = _free_port()
    env = {
        **os.environ,
        "SIM_XMPP_SECRETS": str(tmp_path / "secrets"),  # `server init` makes a password per account there
        "SIM_XMPP_SERVER": f"127.0.0.1:{port}",
        "SIM_XMPP_CA_FILE": str(tmp_path / "xmpp" / "certs" / "observatory.local.crt"),
        "SIM_XMPP_POLICY": str(tmp_path / "xmpp" / "access.policy"),  # also by `server init`
        "SIM_CLOCK_SPEED": SPEED,
        "SIM_WALL_START": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%S"),
        "OBSERVATORY_DATA": str(tmp_path / "data"),
        "NIGHTCREW_SUPERVISOR_SOCKET": str(tmp_path / "supervisor.sock"),
    }
    # As docs/observatory.md: *.yaml robotic/*.yaml shared/operator.yaml
    modules = [*OBSERVATORY.glob("*.yaml"), *OBSERVATORY.glob("robotic/*.yaml")]
    files = [*modules, OBSERVATORY / "shared" / "operator.yaml"]
    nightcrew("server", "init", "xmpp", "--port", str(port), *map(str, files), env=env, cwd=tmp_path)
    nightcrew("server", "start", "xmpp", env=env, cwd=tmp_path)
    try:
        yield env
    finally:
        subprocess.run(
            [sys.executable, "-m", "nightcrew", "server", "stop", "xmpp"], env=env, cwd=tmp_path, check=False
        )


def test_up_runs_a_task_added_with_nightcrew_tasks(environment: dict[str, str], tmp_path: Path) -> None:
    env = environment
    assert "OK" in nightcrew("check", str(OBSERVATORY), env=env, cwd=tmp_path)
    (tmp_path / "data").mkdir()
    (tmp_path / "m39.yaml").write_text(TASK, encoding="utf-8")
    database = str(tmp_path / "data" / "tasks.sqlite")
    added = nightcrew("tasks", "--db", database, "add", "m39.yaml", env=env, cwd=tmp_path)
    assert "task 1" in added, added
    with open(tmp_path / "supervisor.log", "wb") as log:
        up = subprocess.Popen(
            [sys.executable, "-m", "nightcrew", "up", str(OBSERVATORY), "--log-dir", "logs"],
            env=env,
            cwd=tmp_path,
            stdout=subprocess.DEVNULL,
            stderr=log,
        )
    try:
        state = ""
        deadline = time.monotonic() + TASK_TIMEOUT
        while time.monotonic() < deadline and up.poll() is None:
            shown = nightcrew("tasks", "--db", database, "show", "1", env=env, cwd=tmp_path)
            state = next(line for line in shown.splitlines() if line.startswith("state:"))
            if "COMPLETED" in state or "CANCELED" in state:
                break
            time.sleep(2.0)
        assert up.poll() is None, (tmp_path / "supervisor.log").read_text()
        assert "COMPLETED" in state, _logs(tmp_path, state)
        frames = tmp_path / "data" / "frames"
        science = sorted(frames.rglob("*object*.fits"))
        assert len(science) >= 2, [path.name for path in frames.rglob("*.fits")]
        assert (tmp_path / "data" / "events.jsonl").stat().st_size > 0
    finally:
        if up.poll() is None:
            up.send_signal(signal.SIGTERM)
        up.wait(timeout=120)
    assert up.returncode == 0, (tmp_path / "supervisor.log").read_text()


def _logs(tmp_path: Path, state: str) -> str:
    """The task's state and the tails of the robotic modules' logs, for a failure message."""
    parts = [state]
    for name in ("scheduler", "mastermind", "weather", "roof", "camera"):
        path = tmp_path / "logs" / f"{name}.log"
        if path.is_file():
            parts.append(f"--- {name}\n" + path.read_text(errors="replace")[-1500:])
    return "\n".join(parts)
