"""SSHFile and SMBFile across a link that goes silent: a bounded error naming the server, then
the same root works again once the link is mended (the servers run on a simulated host)."""

from __future__ import annotations

import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.testing.hosts import OUTSIDE, Hosts, hosts_missing
from nightcrew.testing.samba import SambaServer, samba_missing
from nightcrew.testing.sshd import SshServer, sshd_missing
from nightcrew.vfs import FileRoot, SMBFile, SSHFile, VfsError
from tests.vfs.remote_servers import require

TIMEOUT = 3.0  # seconds an operation may take: the roots' own bound, small for the test


@pytest.fixture
def servers(tmp_path: Path) -> Iterator[tuple[Hosts, SshServer, SambaServer]]:
    require(hosts_missing() + sshd_missing() + samba_missing())
    with Hosts(["files"], outside=["files"]) as hosts:
        host = hosts["files"]
        address = host.address(OUTSIDE)
        ssh = SshServer(tmp_path / "sshd", host=address, port=22, wrap=host.command)
        samba = SambaServer(tmp_path / "samba", host=address, port=445, wrap=host.command)
        ssh.start()
        samba.start()
        try:
            yield hosts, ssh, samba
        finally:
            ssh.stop()
            samba.stop()


def roots(ssh: SshServer, samba: SambaServer) -> dict[str, FileRoot]:
    return {
        "ssh": SSHFile(
            ssh.host, username=ssh.username, root=str(ssh.files), client_keys=[str(ssh.client_key)],
            known_hosts=str(ssh.known_hosts), timeout=TIMEOUT, connect_timeout=TIMEOUT,
        ),
        "smb": SMBFile(
            samba.host, share=samba.share, username=samba.username, password=samba.password,
            timeout=TIMEOUT, connect_timeout=TIMEOUT,
        ),
    }  # fmt: skip


@pytest.mark.parametrize("kind", ["ssh", "smb"])
async def test_a_silent_link_gives_a_bounded_error_and_the_root_recovers(
    servers: tuple[Hosts, SshServer, SambaServer], kind: str
) -> None:
    hosts, ssh, samba = servers
    root = roots(ssh, samba)[kind]
    try:
        await root.write_bytes("a.fits", b"before")  # connected
        hosts.cut("files", OUTSIDE)
        started = time.monotonic()
        silent = rf"^a\.fits: {kind.upper()} server .*{ssh.host}.* did not answer within 3 s"
        with pytest.raises(VfsError, match=silent):
            await root.read_bytes("a.fits")
        waited = time.monotonic() - started
        assert waited < 2 * TIMEOUT  # bounded by the root's timeout: a silent server is not retried
        hosts.restore("files", OUTSIDE)
        await root.write_bytes("a.fits", b"after")
        assert await root.read_bytes("a.fits") == b"after"
        print(f"{kind}: error after {waited:.1f} s on the silent link; works again after the restore")
    finally:
        await root.close()
