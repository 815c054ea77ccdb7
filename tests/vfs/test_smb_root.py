"""The VFS contract suite on an SMBFile root against a real Samba server on 127.0.0.1, and what
only SMB has: logins, unreachable servers."""

from __future__ import annotations

import uuid
from collections.abc import AsyncIterator

import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.testing.processes import free_port
from nightcrew.testing.samba import SambaServer
from nightcrew.vfs import FileRoot, SMBFile, VfsError, VirtualFileSystem
from tests.vfs.remote_servers import samba_fixture  # noqa: F401 - the session's server
from tests.vfs.test_contract import *  # noqa: F403 - every contract test, run on this root


def smb_root(server: SambaServer, directory: str, **options: object) -> SMBFile:
    return SMBFile(
        server.host,
        port=server.port,
        share=server.share,
        username=server.username,
        password=server.password,
        root=directory,
        **options,  # type: ignore[arg-type]
    )


@pytest.fixture
def directory() -> str:
    """A fresh directory in the share for each test."""
    return uuid.uuid4().hex[:12]


@pytest.fixture
async def root(samba: SambaServer, directory: str) -> AsyncIterator[FileRoot]:
    remote = smb_root(samba, directory)
    try:
        yield remote
    finally:
        await remote.close()


async def test_files_land_in_the_share(samba: SambaServer, directory: str) -> None:
    async with VirtualFileSystem({"smb": smb_root(samba, directory)}) as vfs:
        await vfs.write_bytes("/smb/night/a.fits", b"photons")
    assert (samba.files / directory / "night" / "a.fits").read_bytes() == b"photons"
    assert sorted(p.name for p in (samba.files / directory / "night").iterdir()) == ["a.fits"]


async def test_a_wrong_password_is_refused(samba: SambaServer, directory: str) -> None:
    root = SMBFile(
        samba.host, port=samba.port, share=samba.share, username=samba.username,
        password="wrong", root=directory,
    )  # fmt: skip
    async with VirtualFileSystem({"smb": root}) as vfs:
        refused = (
            rf"^/smb/a\.fits: SMB server observer@127\.0\.0\.1:{samba.port}/files refused the login: "
            "wrong user name or password$"
        )
        with pytest.raises(VfsError, match=refused):
            await vfs.write_bytes("/smb/a.fits", b"x")
    assert not (samba.files / directory).exists()


async def test_an_unreachable_server_is_named() -> None:
    port = free_port()
    root = SMBFile("127.0.0.1", port=port, share="files", username="u", password="p", connect_timeout=5)
    async with VirtualFileSystem({"smb": root}) as vfs:
        unreachable = rf"^/smb/a\.fits: cannot reach SMB server u@127\.0\.0\.1:{port}/files: "
        with pytest.raises(VfsError, match=unreachable):
            await vfs.read_bytes("/smb/a.fits")


async def test_a_missing_share_is_named(samba: SambaServer) -> None:
    root = SMBFile(
        samba.host, port=samba.port, share="nope", username=samba.username, password=samba.password
    )
    async with VirtualFileSystem({"smb": root}) as vfs:
        with pytest.raises(
            VfsError, match=rf"^/smb/a\.fits: SMB server observer@.*:{samba.port}/nope: no such share$"
        ):
            await vfs.read_bytes("/smb/a.fits")


def test_bad_options_are_refused() -> None:
    with pytest.raises(
        InvalidArgumentError, match=r"SMBFile share must be a plain non-empty name, got 'a\\\\b'"
    ):
        SMBFile("h", share="a\\b", username="u", password="p")
    with pytest.raises(InvalidArgumentError, match=r"SMBFile port must be 1\.\.65535, got 70000"):
        SMBFile("h", share="s", username="u", password="p", port=70000)
    with pytest.raises(InvalidArgumentError, match="SMBFile connect_timeout and timeout must be > 0"):
        SMBFile("h", share="s", username="u", password="p", timeout=-1)
