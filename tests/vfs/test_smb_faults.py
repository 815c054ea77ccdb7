"""SMBFile when its server goes away: errors that name it, reconnecting, no half-written file."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.testing.samba import SambaServer, samba_missing
from nightcrew.vfs import SMBFile
from tests.vfs.faults import reconnects_after_the_server_restarts, write_cut_off_by_a_dead_server
from tests.vfs.remote_servers import require


@pytest.fixture
def server(tmp_path: Path) -> Iterator[SambaServer]:
    """A server of this test's own: the tests stop and restart it."""
    require(samba_missing())
    samba = SambaServer(tmp_path / "samba")
    samba.start()
    try:
        yield samba
    finally:
        samba.stop()


def smb_root(server: SambaServer) -> SMBFile:
    return SMBFile(
        server.host, port=server.port, share=server.share, username=server.username,
        password=server.password, connect_timeout=10, timeout=30,
    )  # fmt: skip


async def test_reconnects_after_the_server_restarts(server: SambaServer) -> None:
    down = rf"SMB server .*127\.0\.0\.1:{server.port}"
    await reconnects_after_the_server_restarts(smb_root(server), down, server.stop, server.start)


async def test_a_write_cut_off_by_a_dead_server_leaves_the_old_file(server: SambaServer) -> None:
    root = smb_root(server)
    written = await write_cut_off_by_a_dead_server(root, server.files, server.stop, server.start)
    print(f"server stopped with {written} bytes in the temporary file; the target kept its old content")
