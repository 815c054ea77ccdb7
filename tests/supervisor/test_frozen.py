"""A module process whose event loop stops beating is reported frozen and killed (no server: the module
runs on the in-process comm)."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.supervisor import ModuleFile, ModuleProcess, RestartPolicy
from nightcrew.testing import wait_for

FROZEN_AFTER = 2.0
WITHIN = 60.0  # wall seconds for a process to start on a loaded machine


async def test_a_stopped_process_is_reported_frozen_and_killed(tmp_path: Path) -> None:
    config = tmp_path / "m.yaml"
    config.write_text("class: nightcrew.modules.Module\n")
    process = ModuleProcess(
        ModuleFile("m", config),
        log_dir=tmp_path,
        log_format="text",
        policy=RestartPolicy(first_delay=3.0),
        frozen_after=FROZEN_AFTER,
    )
    log = tmp_path / "m.log"
    process.start()
    try:
        # ready: its event loop runs, and beats
        await wait_for(lambda: log.exists() and "m is ready" in log.read_text(), WITHIN, message="ready")
        pid = process.status().pid
        assert pid is not None
        os.kill(pid, signal.SIGSTOP)
        # frozen from the missed beats until the restart (after the backoff delay, 3 s here; the
        # restart itself is tested with Prosody in tests/safety/test_watchdog_processes.py)
        await wait_for(lambda: process.status().last_exit != "", WITHIN, message="killed")
        status = process.status()
        assert (status.state, status.pid) == ("frozen", None)
        assert status.last_exit == f"frozen (no heartbeat for {FROZEN_AFTER:g} s); killed by SIGKILL"
    finally:
        await process.stop()
    assert process.status().state == "stopped"


@pytest.mark.parametrize("value", ["-1", "0.5", "nan", "inf", "1e400", "abc"])
def test_frozen_after_is_0_or_1_to_86400_seconds(value: str, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exited:
        main(["up", "modules", "--frozen-after", value])
    assert exited.value.code == 2
    assert "argument --frozen-after: " in capsys.readouterr().err.splitlines()[-1]
