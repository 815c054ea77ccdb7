"""SSHFile when its server goes away: errors that name it, reconnecting, no half-written file, and
an ImageWatcher and an ImageWriter copying to it that lose nothing and finish once the server is
back."""

from __future__ import annotations

import hashlib
import io
import logging
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from nightcrew.events import NewImageEvent
from nightcrew.modules.image import ImageWatcher, ImageWriter
from nightcrew.testing import Observatory
from nightcrew.testing.sshd import SshServer, sshd_missing
from nightcrew.vfs import LocalFile, SSHFile, VirtualFileSystem
from tests.vfs.faults import (
    reconnects_after_the_server_restarts,
    temp_files,
    wait_until,
    write_cut_off_by_a_dead_server,
)
from tests.vfs.remote_servers import require


@pytest.fixture
def server(tmp_path: Path) -> Iterator[SshServer]:
    """A server of this test's own: the tests stop and restart it."""
    require(sshd_missing())
    sshd = SshServer(tmp_path / "sshd")
    sshd.start()
    try:
        yield sshd
    finally:
        sshd.stop()


def ssh_root(server: SshServer) -> SSHFile:
    return SSHFile(
        server.host, port=server.port, username=server.username, root=str(server.files),
        client_keys=[str(server.client_key)], known_hosts=str(server.known_hosts),
        connect_timeout=10, timeout=30,
    )  # fmt: skip


async def test_reconnects_after_the_server_restarts(server: SshServer) -> None:
    down = rf"SSH server .*:{server.port}"
    await reconnects_after_the_server_restarts(ssh_root(server), down, server.stop, server.start)


async def test_a_write_cut_off_by_a_dead_server_leaves_the_old_file(server: SshServer) -> None:
    root = ssh_root(server)
    written = await write_cut_off_by_a_dead_server(root, server.files, server.stop, server.start)
    print(f"server stopped with {written} bytes in the temporary file; the target kept its old content")


async def test_image_watcher_loses_nothing_while_the_server_is_down(
    server: SshServer, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.WARNING, logger="nightcrew.modules.image.watcher")
    watch = tmp_path / "watch"
    rng = np.random.default_rng(5)
    checksums = {}
    for index in range(20):  # a few MB each: a copy takes long enough to be cut in the middle
        data = rng.integers(0, 256, size=int(rng.integers(4, 9) << 20), dtype=np.uint8).tobytes()
        (watch / "night").mkdir(parents=True, exist_ok=True)
        (watch / "night" / f"img-{index:02d}.fits").write_bytes(data)
        checksums[f"night/img-{index:02d}.fits"] = hashlib.sha256(data).hexdigest()
    destination = server.files / "raw"

    def copies_whole() -> None:
        """Every file visible at the destination is a whole, verified copy, and every deleted
        original has one."""
        for path in destination.rglob("*.fits"):
            name = path.relative_to(destination).as_posix()
            assert hashlib.sha256(path.read_bytes()).hexdigest() == checksums[name], f"{name} half-written"
        for name in checksums:
            if not (watch / name).exists():
                assert (destination / name).exists(), f"{name} deleted without a copy"

    def failures() -> int:
        return sum("retrying /remote/raw" in record.getMessage() for record in caplog.records)

    vfs = VirtualFileSystem({"remote": ssh_root(server)})
    async with Observatory(speed=10.0, vfs=vfs) as obs:
        watcher = await obs.start(
            ImageWatcher, "watcher", watch=str(watch), destinations=["/remote/raw"],
            interval=1.0, retry_delay=2.0, max_retry_delay=8.0,
        )  # fmt: skip

        def copy_under_way() -> bool:
            try:
                return watcher.moved >= 3 and any(p.stat().st_size for p in temp_files(destination / "night"))
            except FileNotFoundError:  # renamed into place meanwhile
                return False

        await wait_until(copy_under_way, "a copy under way after the first three")
        server.stop()  # in the middle of a copy
        moved_when_stopped = watcher.moved
        await wait_until(lambda: failures() >= 2, "two failed tries")
        copies_whole()
        assert watcher.moved < len(checksums)
        server.start()
        await wait_until(lambda: watcher.moved == len(checksums), "every file moved")
        copies_whole()
    await vfs.close()
    assert not list((watch / "night").glob("*.fits"))
    assert sorted(p.relative_to(destination).as_posix() for p in destination.rglob("*.fits")) == sorted(
        checksums
    )
    orphans = temp_files(destination / "night")
    print(
        f"{moved_when_stopped} of {len(checksums)} moved when sshd stopped; {failures()} failed tries; "
        f"all {len(checksums)} verified at the destination afterwards; {len(orphans)} orphaned (hidden) "
        "temporary file of the copy cut off"
    )


def fits_frame(index: int, rng: np.random.Generator) -> bytes:
    """A FITS file of a few MB whose DATE-OBS names the copy (a copy takes long enough to be cut)."""
    from astropy.io import fits  # type: ignore[import-untyped]

    hdu = fits.PrimaryHDU(rng.integers(0, 60000, size=(1024, int(rng.integers(1024, 2048))), dtype=np.uint16))
    hdu.header["DATE-OBS"] = f"2026-11-10T20:{index:02d}:00"
    hdu.header["IMAGETYP"] = "object"
    with io.BytesIO() as out:
        hdu.writeto(out)
        return out.getvalue()


async def test_image_writer_retries_copies_while_the_server_is_down(
    server: SshServer, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.WARNING, logger="nightcrew.modules.image.writer")
    rng = np.random.default_rng(7)
    checksums = {}
    (tmp_path / "images").mkdir()
    for index in range(12):
        data = fits_frame(index, rng)
        (tmp_path / "images" / f"frame-{index:02d}.fits").write_bytes(data)
        checksums[f"2026-11-10T20-{index:02d}-00-object.fits"] = hashlib.sha256(data).hexdigest()
    destination = server.files / "raw"

    def copies_whole() -> None:
        for path in destination.glob("*.fits"):
            assert hashlib.sha256(path.read_bytes()).hexdigest() == checksums[path.name], (
                f"{path.name} half-written"
            )

    def failures() -> int:
        return sum("trying again in" in record.getMessage() for record in caplog.records)

    vfs = VirtualFileSystem({"remote": ssh_root(server), "images": LocalFile(str(tmp_path / "images"))})
    async with Observatory(speed=10.0, vfs=vfs) as obs:
        writer = await obs.start(
            ImageWriter, "writer", pattern="/remote/raw/{DATE-OBS}-{IMAGETYP}.fits",
            retry_delay=2.0, max_retry_delay=8.0,
        )  # fmt: skip
        for index in range(len(checksums)):
            await writer.on_new_image(NewImageEvent(filename=f"/images/frame-{index:02d}.fits"), "camera")

        def copy_under_way() -> bool:
            try:
                return len(writer.written) >= 2 and any(p.stat().st_size for p in temp_files(destination))
            except FileNotFoundError:  # renamed into place meanwhile
                return False

        await wait_until(copy_under_way, "a copy under way after the first two")
        server.stop()  # in the middle of a copy
        written_when_stopped = len(writer.written)
        await wait_until(lambda: failures() >= 2, "two failed tries")
        copies_whole()
        assert len(writer.written) < len(checksums) and writer.waiting > 0
        server.start()
        await wait_until(lambda: len(writer.written) == len(checksums), "every image copied")
        copies_whole()
        assert writer.waiting == 0
    await vfs.close()
    assert sorted(p.name for p in destination.glob("*.fits")) == sorted(checksums)
    print(
        f"{written_when_stopped} of {len(checksums)} copied when sshd stopped; {failures()} failed tries; "
        f"all {len(checksums)} whole at the destination after the restart"
    )
