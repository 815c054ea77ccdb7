"""Session-wide private SSH and SMB servers for the remote-root tests (skip only off CI)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.testing.samba import SambaServer, samba_missing
from nightcrew.testing.sshd import SshServer, sshd_missing


def require(missing: list[str]) -> None:
    """Skip when something is missing, but fail under CI=true (CI cannot pass by skipping)."""
    if not missing:
        return
    message = "missing: " + ", ".join(missing) + " (make system-deps)"
    if os.environ.get("CI") == "true":
        pytest.fail(message)
    pytest.skip(message)


@pytest.fixture(scope="session", name="sshd")
def sshd_fixture(tmp_path_factory: pytest.TempPathFactory) -> Iterator[SshServer]:
    """One OpenSSH server on a free 127.0.0.1 port for the session."""
    require(sshd_missing())
    server = SshServer(Path(tmp_path_factory.mktemp("sshd")))
    server.start()
    try:
        yield server
    finally:
        server.stop()


@pytest.fixture(scope="session", name="samba")
def samba_fixture(tmp_path_factory: pytest.TempPathFactory) -> Iterator[SambaServer]:
    """One Samba server on a free 127.0.0.1 port for the session."""
    require(samba_missing())
    server = SambaServer(Path(tmp_path_factory.mktemp("samba")))
    server.start()
    try:
        yield server
    finally:
        server.stop()
