"""The ArchiveFile VFS root: ImageWatcher moves frames into a running archive (copy, verify by the
archive's checksum, delete), and the archive reads and lists like a directory tree.

The watcher runs on the real clock: the archive's PostgreSQL is another process, which virtual
time cannot see (docs/concepts.md#clock).
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from nightcrew.clock import RealClock
from nightcrew.modules.image import ImageWatcher
from nightcrew.testing import Observatory
from nightcrew.testing.archive import RunningArchive, fits_frame
from nightcrew.vfs import ArchiveFile, VfsError, VfsFileNotFoundError, VfsFormatError, VirtualFileSystem

from .conftest import Client

PATIENCE = 60.0  # wall seconds for what takes a fraction of one


@pytest.fixture
async def real_time() -> AsyncIterator[Observatory]:
    async with Observatory(clock=RealClock()) as obs:
        yield obs


async def test_image_watcher_moves_frames_into_the_archive(
    real_time: Observatory, archive: RunningArchive, client: Client, tmp_path: Path
) -> None:
    watch = tmp_path / "watch"
    (watch / "night").mkdir(parents=True)
    frames = {f"night/img-{i}.fits": fits_frame(seed=i, date_obs=f"2026-11-24T2{i}:00:00") for i in range(3)}
    for name, data in frames.items():
        (watch / name).write_bytes(data)
    # A file the archive refuses stays. Named to sort last: the watcher backs a destination off
    # after any failure, so a refused file sorted first would hold the others back each sweep.
    (watch / "night/zz-broken.fits").write_bytes(b"SIMPLE  =                    T" + b" " * 100)
    async with VirtualFileSystem({"archive": ArchiveFile(archive.url, token=archive.token)}) as vfs:
        watcher = await real_time.start(
            ImageWatcher,
            "watcher",
            watch=str(watch),
            destinations=["/archive/raw"],
            pattern="**/*.fits",
            interval=0.05,
            retry_delay=0.05,
            max_retry_delay=0.2,
            vfs=vfs,
        )
        await real_time.wait_for(lambda: watcher.moved == 3, PATIENCE, message="3 frames moved")
        status, body = await client.get("/frames/", ordering="DATE_OBS")
        assert status == 200
        assert [(f["basename"], f["sha256"]) for f in body["results"]] == [
            (Path(name).name, hashlib.sha256(data).hexdigest()) for name, data in frames.items()
        ]
        assert sorted(p.name for p in watch.rglob("*.fits")) == ["zz-broken.fits"]  # refused, so kept
        assert watcher.pending == 1
        await real_time.close()  # the watcher stops before its VFS closes


async def test_archive_root_reads_lists_and_refuses_what_an_archive_must(archive: RunningArchive) -> None:
    data = fits_frame(instrument="cam 1")
    async with VirtualFileSystem({"archive": ArchiveFile(archive.url, token=archive.token)}) as vfs:
        await vfs.write_bytes("/archive/anything/a.fits", data)
        await vfs.write_bytes("/archive/again/a.fits", data)  # the same bytes again: already there
        assert await vfs.listdir("/archive") == ["20261124"]
        assert await vfs.listdir("/archive/20261124") == ["cam_1"]
        assert await vfs.find("/archive/**/*.fits") == ["/archive/20261124/cam_1/a.fits"]
        assert await vfs.read_bytes("/archive/20261124/cam_1/a.fits") == data
        assert await vfs.size("/archive/a.fits") == len(data)
        assert await vfs.checksum("/archive/a.fits") == hashlib.sha256(data).hexdigest()
        assert await vfs.checksum("/archive/a.fits", "md5") == hashlib.md5(data).hexdigest()
        assert await vfs.exists("/archive/20261124/cam_1") and not await vfs.exists("/archive/b.fits")
        with pytest.raises(
            VfsFileNotFoundError, match=re.escape("/archive/b.fits: no such frame in the archive")
        ):
            await vfs.read_bytes("/archive/b.fits")
        with pytest.raises(
            VfsFormatError, match=re.escape("refused the file: missing FITS keywords INSTRUME")
        ):
            await vfs.write_bytes("/archive/c.fits", data.replace(b"INSTRUME=", b"COMMENT  "))
        with pytest.raises(VfsError, match=re.escape("a different frame is stored as a.fits")):
            await vfs.write_bytes("/archive/a.fits", fits_frame(seed=9))
        with pytest.raises(VfsError, match="the archive keeps its frames"):
            await vfs.remove("/archive/a.fits")
    async with VirtualFileSystem({"archive": ArchiveFile(archive.url, token="wrong-token-wrong")}) as vfs:
        with pytest.raises(VfsError, match=re.escape("answered 401: uploads need the archive's token")):
            await vfs.write_bytes("/archive/d.fits", fits_frame(seed=3))
