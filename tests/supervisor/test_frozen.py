"""A module process whose event loop stops beating is reported frozen and killed (no server: the module
runs on the in-process comm)."""

from __future__ import annotations

import os
import signal
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.interfaces import IModule, ModuleState
from nightcrew.modules import Module
from nightcrew.supervisor import ModuleFile, ModuleProcess, ModuleStatus, RestartPolicy
from nightcrew.supervisor._presence import SupervisorPresence
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


async def test_the_supervisor_on_the_bus_is_in_error_while_a_module_is_frozen(tmp_path: Path) -> None:
    """What the console and ``nightcrew modules`` show of the supervisor (``nightcrew up --comm``)."""
    comm_file = tmp_path / "supervisor.yaml"
    comm_file.write_text("class: nightcrew.comm.local.LocalComm\nname: supervisor\n")
    frozen = ModuleStatus("mastermind", "frozen", None, 0, 0.0, "", "no heartbeat for 30 s", "m.yaml")
    presence = SupervisorPresence(comm_file, lambda: [frozen])
    observer = Module(comm=LocalComm("observer", network=LocalNetwork.default()))
    await presence.open()
    await observer.open()
    try:
        supervisor = await observer.comm.proxy("supervisor", IModule)
        await wait_for(lambda: _state_is(supervisor, ModuleState.ERROR), 10, message="supervisor in error")
        assert await supervisor.get_error_string() == "mastermind frozen: no heartbeat for 30 s"
    finally:
        await observer.close()
        await presence.close()


async def _state_is(module: IModule, state: ModuleState) -> bool:
    return ModuleState(await module.get_state()) is state
