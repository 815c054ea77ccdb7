"""A module process whose event loop stops beating is reported frozen and killed (no server: the module
runs on the in-process comm)."""

from __future__ import annotations

import dataclasses
import os
import signal
import tempfile
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


async def test_nightcrew_modules_shows_what_the_supervisor_here_finds_frozen(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A frozen process keeps its last presence in the room: ``nightcrew modules`` asks this
    computer's supervisor (its control socket) and shows ``frozen`` where it says so."""
    from nightcrew.cli.modules import _list
    from nightcrew.supervisor._control import ControlServer

    frozen = ModuleStatus("watchdog", "frozen", 4242, 0, 0.0, "", "no heartbeat for 30 s", "watchdog.yaml")
    running = ModuleStatus("roof", "running", 4243, 0, 0.0, "", "", "roof.yaml")

    async def answer(request: dict[str, object]) -> dict[str, object]:
        return {"modules": [dataclasses.asdict(frozen), dataclasses.asdict(running)]}

    socket = Path(tempfile.mkdtemp(prefix="nc-frozen-")) / "control.sock"
    comm_file = tmp_path / "operator.yaml"
    comm_file.write_text("class: nightcrew.comm.local.LocalComm\nname: operator\n")
    network = LocalNetwork.default()
    modules = [Module(comm=LocalComm(name, network=network)) for name in ("roof", "watchdog")]
    server = ControlServer(socket, answer)
    for module in modules:
        await module.open()
    try:
        monkeypatch.setenv("NIGHTCREW_SUPERVISOR_SOCKET", str(socket))
        assert _rows(await _list(str(comm_file))) == {"roof": "ready", "watchdog": "ready"}  # no supervisor
        await server.open()
        assert _rows(await _list(str(comm_file))) == {"roof": "ready", "watchdog": "frozen"}
    finally:
        await server.close()
        for module in modules:
            await module.close()


def _rows(table: str) -> dict[str, str]:
    return {line.split()[0]: line.split()[1] for line in table.splitlines()}
