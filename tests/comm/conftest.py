"""The network fixture: every contract test runs once per transport.

``local`` is the in-process LocalComm; ``prosody`` and ``ejabberd`` run XmppComm against real
servers started once per session (see xmpp_servers.py). Each test gets fresh modules and, on
XMPP, a room of its own, so tests cannot see each other's modules or events.
"""

from __future__ import annotations

import uuid
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import Any, TypeVar

import pytest

from nightcrew.comm.base import Comm
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.modules import Module
from nightcrew.server import Account, init_server, register_account, start_server, stop_server

from .xmpp_servers import DOMAIN, MODULE_NAMES, PASSWORD, XmppServer, free_port, require_command

M = TypeVar("M", bound=Module)


class Network:
    """Builds modules on one transport and closes them after the test."""

    def __init__(self, kind: str, server: XmppServer | None = None) -> None:
        self.kind = kind
        self.server = server
        self.room = f"test-{uuid.uuid4().hex[:10]}"
        self._local = LocalNetwork()
        self._modules: list[Module] = []

    def comm(self, name: str) -> Comm:
        if self.server is not None:
            # The contract is about the transport, not access: open, as a user would say it.
            return self.server.comm(name, room=self.room, policy="open")
        return LocalComm(name, network=self._local)

    async def start(self, cls: type[M], name: str, **kwargs: Any) -> M:
        module = cls(comm=self.comm(name), **kwargs)
        self._modules.append(module)
        await module.open()
        return module

    async def close(self) -> None:
        for module in reversed(self._modules):
            await module.close()


class _ProsodyControl:
    def __init__(self, directory: Path) -> None:
        self.directory = directory

    def register(self, account: Account) -> None:
        register_account(self.directory, account)

    def start(self) -> None:
        start_server(self.directory)

    def stop(self) -> None:
        stop_server(self.directory)


@pytest.fixture(scope="session")
def prosody_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[XmppServer]:
    require_command("prosody", "prosody")
    directory = tmp_path_factory.mktemp("prosody")
    port = free_port()
    init_server(directory, [], host="127.0.0.1", port=port, domains=[DOMAIN])
    control = _ProsodyControl(directory)
    control.start()
    try:
        yield XmppServer("prosody", directory, port, control, str(directory / "certs" / f"{DOMAIN}.crt"))
    finally:
        control.stop()


@pytest.fixture(scope="session")
def ejabberd_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[XmppServer]:
    from .ejabberd import running_ejabberd

    require_command("ejabberdctl", "ejabberd")
    with running_ejabberd(MODULE_NAMES, PASSWORD) as server:
        yield server


_TRANSPORTS = [
    "local",
    pytest.param("prosody", marks=pytest.mark.xmpp),
    pytest.param("ejabberd", marks=pytest.mark.xmpp),
]


@pytest.fixture(params=_TRANSPORTS)
async def network(request: pytest.FixtureRequest) -> AsyncIterator[Network]:
    server = None if request.param == "local" else request.getfixturevalue(f"{request.param}_server")
    net = Network(request.param, server)
    try:
        yield net
    finally:
        await net.close()


@pytest.fixture(params=_TRANSPORTS[1:])
async def xmpp_network(request: pytest.FixtureRequest) -> AsyncIterator[Network]:
    """Like ``network``, for tests of what only the XMPP transport has (logins, reconnects)."""
    net = Network(request.param, request.getfixturevalue(f"{request.param}_server"))
    try:
        yield net
    finally:
        await net.close()


@pytest.fixture
async def prosody_network(prosody_server: XmppServer) -> AsyncIterator[Network]:
    """A Network on Prosody only (tests that restart the server or run processes)."""
    net = Network("prosody", prosody_server)
    try:
        yield net
    finally:
        await net.close()
