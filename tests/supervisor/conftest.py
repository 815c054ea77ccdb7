"""A Prosody of the supervisor tests' own (they stop and restart it), and a supervised directory.

:class:`SupervisedDirectory` writes module files onto that server, runs ``nightcrew up`` on them
as a child process and talks to it through its control socket, as ``nightcrew status`` does.
"""

from __future__ import annotations

import asyncio
import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import Any

import pytest

from nightcrew.comm.xmpp import XmppComm
from nightcrew.modules import Module
from nightcrew.server import Account, init_server, register_account, start_server, stop_server
from nightcrew.supervisor import send_request
from nightcrew.testing.processes import free_port
from tests.comm.xmpp_servers import DOMAIN, PASSWORD, require_command

REPOSITORY = Path(__file__).resolve().parents[2]
#: Wall seconds for a module process to come up (imports, login, room) on a loaded machine.
START_TIMEOUT = 60.0


class Prosody:
    """A private Prosody: its directory, port and certificate; accounts registered on demand."""

    def __init__(self, directory: Path, port: int) -> None:
        self.directory = directory
        self.port = port
        self.ca_file = directory / "certs" / f"{DOMAIN}.crt"
        self._registered: dict[str, str] = {}  # account -> its password

    @property
    def address(self) -> str:
        return f"127.0.0.1:{self.port}"

    def account(self, name: str, password: str = PASSWORD) -> None:
        """Register ``name`` on first use (again for a new password)."""
        if self._registered.get(name) != password:
            register_account(self.directory, Account(name, DOMAIN, password))
            self._registered[name] = password

    def pid(self) -> int:
        return int((self.directory / "prosody.pid").read_text())

    def start(self) -> None:
        start_server(self.directory)

    def stop(self) -> None:
        stop_server(self.directory)


@pytest.fixture(scope="module")
def prosody(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Prosody]:
    require_command("prosody", "prosody")
    directory = tmp_path_factory.mktemp("prosody")
    port = free_port()
    init_server(directory, [], host="127.0.0.1", port=port, domains=[DOMAIN])
    server = Prosody(directory, port)
    server.start()
    try:
        yield server
    finally:
        server.stop()


class SupervisedDirectory:
    """Module files in a directory, the ``nightcrew up`` process supervising them, its socket."""

    def __init__(self, prosody: Prosody, directory: Path, room: str) -> None:
        self.prosody = prosody
        self.directory = directory
        self.room = room
        # A Unix socket path must stay below 108 bytes: pytest's tmp_path can be longer.
        self.socket = Path(tempfile.mkdtemp(prefix="nc-sup-")) / "control.sock"
        self.log_dir = directory.parent / "logs"
        self.process: subprocess.Popen[bytes] | None = None
        (directory / "xmpp.yaml").write_text(
            "class: nightcrew.comm.xmpp.XmppComm\n"
            f"password: {PASSWORD}\nserver: {prosody.address}\nroom: {room}\nca_file: {prosody.ca_file}\n"
            "policy: open\n"  # these tests are about supervision, not access (tests/security)
        )

    def operator_comm(self, **options: Any) -> XmppComm:
        """A comm for the account ``operator`` (registered here) in the test's room (``options``:
        more of XmppComm's, e.g. ``policy``)."""
        self.prosody.account("operator")
        return XmppComm(
            f"operator@{DOMAIN}",
            PASSWORD,
            server=self.prosody.address,
            room=self.room,
            ca_file=str(self.prosody.ca_file),
            **options,
        )

    def env(self) -> dict[str, str]:
        # This checkout's code, also where the venv's editable install is another checkout's.
        return {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPOSITORY / "src"), str(REPOSITORY)])}

    def write_module(self, name: str, cls: str = "nightcrew.modules.Module", **options: Any) -> Path:
        """A module file ``name.yaml`` on the test's server and room (its account registered)."""
        self.prosody.account(name)
        lines = [f"class: {cls}", *(f"{key}: {value}" for key, value in options.items())]
        lines += ["comm:", "  <<: !include xmpp.yaml", f"  jid: {name}@{DOMAIN}"]
        path = self.directory / f"{name}.yaml"
        path.write_text("\n".join(lines) + "\n")
        return path

    def up(self, *options: str) -> None:
        with open(self.directory.parent / "supervisor.log", "wb") as log:
            self.process = subprocess.Popen(
                [sys.executable, "-m", "nightcrew", "up", str(self.directory), "--socket", str(self.socket),
                 "--log-dir", str(self.log_dir), *options],
                cwd=REPOSITORY, env=self.env(), stdout=subprocess.DEVNULL, stderr=log,
            )  # fmt: skip

    def supervisor_log(self) -> str:
        return (self.directory.parent / "supervisor.log").read_text(errors="replace")

    async def request(self, command: str, module: str | None = None, **extra: Any) -> dict[str, Any]:
        return await send_request(self.socket, {"command": command, "module": module, **extra})

    async def status(self) -> dict[str, dict[str, Any]]:
        reply = await self.request("status")
        return {m["name"]: m for m in reply["modules"]}

    async def wait_for_status(self, check: Any, what: str, within: float = START_TIMEOUT) -> dict[str, Any]:
        """Poll the status until ``check(status)`` holds (bounded); the status then."""
        deadline = time.monotonic() + within
        while True:
            assert self.process is not None and self.process.poll() is None, self.supervisor_log()
            if self.socket.exists():
                status = await self.status()
                if check(status):
                    return status
            assert time.monotonic() < deadline, f"{what}: not within {within:g} s\n{self.supervisor_log()}"
            await asyncio.sleep(0.1)

    def terminate(self, timeout: float = 60.0) -> int:
        """SIGTERM to the supervisor; its exit code (it must stop within ``timeout``)."""
        assert self.process is not None
        self.process.send_signal(signal.SIGTERM)
        return self.process.wait(timeout=timeout)

    def kill(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()


@pytest.fixture
async def supervised(prosody: Prosody, tmp_path: Path) -> AsyncIterator[SupervisedDirectory]:
    directory = tmp_path / "modules"
    directory.mkdir()
    supervised = SupervisedDirectory(prosody, directory, room=f"sup-{os.urandom(4).hex()}")
    try:
        yield supervised
    finally:
        supervised.kill()  # after a failure: nothing outlives the test (children die with it)


@pytest.fixture
async def operator(supervised: SupervisedDirectory) -> AsyncIterator[Module]:
    """A module in the test's room, to see the supervised modules come and go."""
    module = Module(comm=supervised.operator_comm())
    await module.open()
    try:
        yield module
    finally:
        await module.close()
