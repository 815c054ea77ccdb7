"""Real XMPP servers for the tests: private instances on free loopback ports in a temp dir.

A test that needs a server which is not installed skips on a developer machine and fails when
``CI=true`` (so CI cannot pass by skipping).
"""

from __future__ import annotations

import os
import shutil
import socket
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

import pytest

from nightcrew.comm.xmpp import XmppComm
from nightcrew.server import Account

DOMAIN = "observatory.test"
PASSWORD = "secret-for-tests"
#: Module names the tests use, registered when a server starts (others are registered on demand).
MODULE_NAMES = [
    "calc", "caller", "plain", "listener", "sender", "watcher", "other", "viewer",
    "telescope", "camera", "operator",
]  # fmt: skip


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


def require_command(command: str, package: str) -> None:
    """Skip (or fail on CI) when ``command`` is missing."""
    if shutil.which(command) is not None:
        return
    message = f"{command} is not installed (apt-get install {package}, or make system-deps)"
    if os.environ.get("CI") == "true":
        pytest.fail(message)
    pytest.skip(message)


class ServerControl(Protocol):
    """What a test may do with a running server."""

    def register(self, account: Account) -> None: ...
    def start(self) -> None: ...
    def stop(self) -> None: ...


@dataclass
class XmppServer:
    """A running private server and the accounts registered on it so far."""

    kind: str
    directory: Path
    port: int
    control: ServerControl
    ca_file: str | None
    registered: dict[str, str] = field(default_factory=dict)  # account -> its password

    @property
    def address(self) -> str:
        return f"127.0.0.1:{self.port}"

    def account(self, name: str, password: str = PASSWORD) -> Account:
        """The account for module ``name``, registered on first use (again for a new password)."""
        account = Account(name, DOMAIN, password)
        if self.registered.get(name) != password:
            self.control.register(account)
            self.registered[name] = password
        return account

    def comm(self, name: str, *, room: str = "nightcrew", **options: object) -> XmppComm:
        account = self.account(name)
        return XmppComm(
            account.jid,
            account.password,
            server=self.address,
            room=room,
            ca_file=self.ca_file,
            **options,  # type: ignore[arg-type]
        )

    def restart(self) -> None:
        self.control.stop()
        self.control.start()
