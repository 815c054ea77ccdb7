"""The VFS contract suite on an SSHFile root against a real OpenSSH server on 127.0.0.1, and what
only SSH has: host keys, logins, atomic writes over a dying link, reconnecting."""

from __future__ import annotations

import uuid
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from nightcrew.testing.sshd import SshServer
from nightcrew.vfs import FileRoot, SSHFile, VfsError, VirtualFileSystem
from tests.vfs.remote_servers import sshd_fixture  # noqa: F401 - the session's server
from tests.vfs.test_contract import *  # noqa: F403 - every contract test, run on this root


def ssh_root(server: SshServer, directory: str, **options: object) -> SSHFile:
    return SSHFile(
        server.host,
        port=server.port,
        username=server.username,
        root=str(server.files / directory),
        client_keys=[str(server.client_key)],
        known_hosts=str(server.known_hosts),
        **options,  # type: ignore[arg-type]
    )


def public_key(private: Path) -> str:
    return Path(f"{private}.pub").read_text()


@pytest.fixture
def directory() -> str:
    """A fresh directory name under the server's files for each test."""
    return uuid.uuid4().hex[:12]


@pytest.fixture
async def root(sshd: SshServer, directory: str) -> AsyncIterator[FileRoot]:
    remote = ssh_root(sshd, directory)
    try:
        yield remote
    finally:
        await remote.close()


async def test_an_unknown_host_key_is_refused(sshd: SshServer, directory: str, tmp_path: Path) -> None:
    other = tmp_path / "known_hosts"
    other.write_text(f"[{sshd.host}]:{sshd.port} {public_key(sshd.client_key)}")  # a key, not the host's
    root = SSHFile(
        sshd.host, port=sshd.port, root=str(sshd.files / directory),
        client_keys=[str(sshd.client_key)], known_hosts=str(other),
    )  # fmt: skip
    async with VirtualFileSystem({"remote": root}) as vfs:
        with pytest.raises(
            VfsError,
            match=r"^/remote/a\.fits: host key of SSH server 127\.0\.0\.1:\d+ not trusted",
        ):
            await vfs.write_bytes("/remote/a.fits", b"x")
    assert not (sshd.files / directory / "a.fits").exists()


async def test_a_missing_known_hosts_file_is_refused(sshd: SshServer, directory: str, tmp_path: Path) -> None:
    root = SSHFile(sshd.host, port=sshd.port, root=directory, known_hosts=str(tmp_path / "none"))
    with pytest.raises(VfsError, match=r"cannot read known_hosts file .*none \(needed to check 127\.0\.0\.1"):
        await root.exists("a.fits")


async def test_a_key_the_server_does_not_know_is_refused(
    sshd: SshServer,
    directory: str,
    tmp_path: Path,
) -> None:
    import asyncssh

    stranger = tmp_path / "stranger"
    stranger.write_bytes(asyncssh.generate_private_key("ssh-ed25519").export_private_key())
    root = SSHFile(
        sshd.host, port=sshd.port, username=sshd.username, root=directory,
        client_keys=[str(stranger)], known_hosts=str(sshd.known_hosts),
    )  # fmt: skip
    with pytest.raises(
        VfsError, match=rf"^a\.fits: SSH server {sshd.username}@127\.0\.0\.1:\d+ refused the login"
    ):
        await root.read_bytes("a.fits")


async def test_an_unreachable_server_is_named(sshd: SshServer) -> None:
    from nightcrew.testing.processes import free_port

    port = free_port()
    root = SSHFile("127.0.0.1", port=port, root="x", known_hosts=str(sshd.known_hosts), connect_timeout=5)
    async with VirtualFileSystem({"remote": root}) as vfs:
        with pytest.raises(
            VfsError, match=rf"^/remote/a\.fits: cannot reach SSH server 127\.0\.0\.1:{port}: "
        ):
            await vfs.read_bytes("/remote/a.fits")


def test_bad_options_are_refused() -> None:
    from nightcrew.errors import InvalidArgumentError

    with pytest.raises(InvalidArgumentError, match="SSHFile host must be"):
        SSHFile("", root="x")
    with pytest.raises(InvalidArgumentError, match=r"SSHFile port must be 1\.\.65535, got 0"):
        SSHFile("h", root="x", port=0)
    with pytest.raises(InvalidArgumentError, match="SSHFile client_keys must be a list"):
        SSHFile("h", root="x", client_keys="id_ed25519")  # type: ignore[arg-type]
    with pytest.raises(InvalidArgumentError, match="SSHFile timeout must be > 0 seconds"):
        SSHFile("h", root="x", timeout=0)
