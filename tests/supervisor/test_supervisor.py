"""``nightcrew up`` on real Prosody: modules as processes, restarted after kill -9, a broken file
reported, control over the socket, a clean stop on SIGTERM."""

from __future__ import annotations

import asyncio
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from nightcrew.interfaces import IModule
from nightcrew.modules import Module
from nightcrew.supervisor import SupervisorError
from nightcrew.testing import wait_for
from tests.comm.xmpp_servers import DOMAIN

from .conftest import START_TIMEOUT, Prosody, SupervisedDirectory

pytestmark = pytest.mark.xmpp


def alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return Path(f"/proc/{pid}/stat").read_text().split()[2] != "Z"


def running(*names: str) -> object:
    return lambda status: all(status[n]["state"] == "running" for n in names)


async def test_kill_9_restarts_and_rejoins_broken_file_reported_others_keep_running(
    supervised: SupervisedDirectory, operator: Module
) -> None:
    supervised.write_module("alpha", "nightcrew.modules.test.StandAlone", message="alpha says hi", interval=1)
    supervised.write_module("beta")
    supervised.up()
    status = await supervised.wait_for_status(running("alpha", "beta"), "both modules running")
    assert set(status) == {"alpha", "beta"}  # xmpp.yaml is included by both: a fragment, not a module
    await wait_for(
        lambda: {"alpha", "beta"} <= set(operator.comm.clients), START_TIMEOUT, message="both in the room"
    )

    # kill -9 of alpha: restarted, back in the room, the reason logged and shown
    first_pid = status["alpha"]["pid"]
    os.kill(first_pid, signal.SIGKILL)
    status = await supervised.wait_for_status(
        lambda s: s["alpha"]["state"] == "running" and s["alpha"]["pid"] not in (None, first_pid),
        "alpha restarted",
    )
    assert status["alpha"]["restarts"] == 1
    assert status["alpha"]["last_exit"] == "killed by SIGKILL"
    await wait_for(lambda: "alpha" in operator.comm.clients, START_TIMEOUT, message="alpha back in the room")
    assert "alpha killed by SIGKILL; restarting in 1 s" in supervised.supervisor_log()

    # beta's file broken on disk, then beta dies: one clear error, alpha untouched
    beta_pid = status["beta"]["pid"]
    (supervised.directory / "beta.yaml").write_text(
        (supervised.directory / "beta.yaml").read_text() + "exposure_speed: 3\n"
    )
    os.kill(beta_pid, signal.SIGKILL)
    status = await supervised.wait_for_status(
        lambda s: s["beta"]["state"] == "broken", "beta reported broken"
    )
    assert "beta.yaml" in status["beta"]["error"] and "exposure_speed" in status["beta"]["error"]
    assert status["alpha"]["state"] == "running" and status["alpha"]["pid"] != first_pid
    assert alive(status["alpha"]["pid"])

    # the CLI shows the same, and exits 3 because not everything runs
    shown = await asyncio.to_thread(
        subprocess.run,
        [sys.executable, "-m", "nightcrew", "status", "--socket", str(supervised.socket)],
        capture_output=True, text=True, timeout=60, env=supervised.env(),
    )  # fmt: skip
    assert shown.returncode == 3, shown.stderr
    lines = shown.stdout.splitlines()
    assert lines[0].split()[:4] == ["MODULE", "STATE", "PID", "RESTARTS"]
    assert lines[1].split()[:4] == ["alpha", "running", str(status["alpha"]["pid"]), "1"]
    assert lines[2].split()[:3] == ["beta", "broken", "-"] and "exposure_speed" in lines[2]

    # fixed and started by hand: running again
    (supervised.directory / "beta.yaml").write_text(
        (supervised.directory / "beta.yaml").read_text().replace("exposure_speed: 3\n", "")
    )
    await supervised.request("start", "beta")
    await supervised.wait_for_status(running("beta"), "beta started again")

    # the module's own log file, through the supervisor
    logs = await supervised.request("logs", "alpha", lines=1000)
    assert any("alpha says hi" in line for line in logs["lines"])
    assert any("alpha is ready" in line for line in logs["lines"])

    # SIGTERM: every module closes itself (leaves the room), then the supervisor exits 0
    pids = [s["pid"] for s in (await supervised.status()).values()]
    assert supervised.terminate() == 0, supervised.supervisor_log()
    assert not any(alive(pid) for pid in pids)
    assert not supervised.socket.exists()
    assert "stopping all modules" in supervised.supervisor_log()


async def test_stop_start_restart_and_unknown_module(supervised: SupervisedDirectory) -> None:
    supervised.write_module("gamma")
    supervised.up()
    status = await supervised.wait_for_status(running("gamma"), "gamma running")
    pid = status["gamma"]["pid"]

    reply = await supervised.request("stop", "gamma")
    assert reply["modules"][0]["state"] == "stopped" and reply["modules"][0]["pid"] is None
    assert not alive(pid)
    await supervised.request("restart", "gamma")
    status = await supervised.wait_for_status(running("gamma"), "gamma restarted")
    assert status["gamma"]["pid"] != pid and status["gamma"]["restarts"] == 0  # by hand: not a crash

    with pytest.raises(SupervisorError, match="no module 'delta'; known: gamma"):
        await supervised.request("stop", "delta")
    with pytest.raises(SupervisorError, match="unknown command 'reboot'"):
        await supervised.request("reboot")
    assert supervised.terminate() == 0


async def test_gives_up_after_the_restart_limit(supervised: SupervisedDirectory, prosody: Prosody) -> None:
    # A module that fails at once on every start (its room does not exist on this domain).
    path = supervised.write_module("crashy")
    path.write_text(path.read_text().replace(f"jid: crashy@{DOMAIN}", "jid: crashy@nowhere.invalid"))
    supervised.up("--max-restarts", "2")
    status = await supervised.wait_for_status(
        lambda s: s["crashy"]["state"] == "failed", "crashy given up", within=120
    )
    assert status["crashy"]["restarts"] == 2
    assert "gave up after too many restarts" in status["crashy"]["error"]
    assert "exited 1" in status["crashy"]["error"]
    assert supervised.terminate() == 0


def test_socket_is_owner_only(supervised: SupervisedDirectory) -> None:
    supervised.write_module("epsilon")
    supervised.up()

    async def check() -> None:
        await supervised.wait_for_status(lambda s: "epsilon" in s, "socket up")

    asyncio.run(check())
    assert supervised.socket.stat().st_mode & 0o777 == 0o600
    assert supervised.socket.parent.stat().st_mode & 0o777 == 0o700
    assert supervised.terminate() == 0


def test_status_without_a_supervisor_is_one_line(tmp_path: Path) -> None:
    done = subprocess.run(
        [sys.executable, "-m", "nightcrew", "status", "--socket", str(tmp_path / "none.sock")],
        capture_output=True, text=True, timeout=60,
    )  # fmt: skip
    assert done.returncode == 1
    assert done.stderr.splitlines() == [
        f"nightcrew: error: no supervisor is running (no answer on {tmp_path / 'none.sock'}; "
        "start one with nightcrew up DIR)"
    ]


async def test_supervisor_heartbeat_on_the_bus(supervised: SupervisedDirectory, operator: Module) -> None:
    supervised.prosody.account("supervisor")
    comm = supervised.directory.parent / "supervisor.yaml"
    comm.write_text(f"<<: !include {supervised.directory / 'xmpp.yaml'}\njid: supervisor@{DOMAIN}\n")
    path = supervised.write_module("zeta")
    supervised.up("--comm", str(comm))
    await wait_for(
        lambda: "supervisor" in operator.comm.clients, START_TIMEOUT, message="supervisor on the bus"
    )
    heartbeat = await operator.comm.proxy("supervisor", IModule)

    async def state_is(state: str) -> bool:
        return str(await heartbeat.get_state()) == state

    await wait_for(lambda: state_is("ready"), START_TIMEOUT, message="supervisor ready")
    status = await supervised.wait_for_status(running("zeta"), "zeta running")
    path.write_text(path.read_text() + "no_such_option: 1\n")
    os.kill(status["zeta"]["pid"], signal.SIGKILL)
    await wait_for(lambda: state_is("error"), START_TIMEOUT, message="supervisor in error")
    error = await heartbeat.get_error_string()
    assert error.startswith("zeta broken: ") and "no_such_option" in error
    path.write_text(path.read_text().replace("no_such_option: 1\n", ""))
    await supervised.request("start", "zeta")
    await wait_for(lambda: state_is("ready"), START_TIMEOUT, message="supervisor ready again")
    assert supervised.terminate() == 0
    await wait_for(lambda: "supervisor" not in operator.comm.clients, 30, message="supervisor left")
