"""The ArchiveFile VFS root: ImageWatcher moves frames into a running archive (copy, verify by the
archive's checksum, delete), and the archive reads and lists like a directory tree.

The watcher runs on the real clock: the archive's PostgreSQL is another process, which virtual
time cannot see (docs/concepts.md#clock).
"""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from nightcrew.clock import RealClock
from nightcrew.events import NewImageEvent
from nightcrew.modules.image import ImageWatcher, ImageWriter
from nightcrew.testing import Observatory
from nightcrew.testing.archive import RunningArchive, fits_frame
from nightcrew.vfs import (
    ArchiveFile,
    LocalFile,
    VfsError,
    VfsFileNotFoundError,
    VfsFormatError,
    VirtualFileSystem,
)

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
    # A file the archive refuses stays, and does not hold back the files after it: it sorts first,
    # and the long retry delay would stop every other file if a refusal counted as an outage.
    (watch / "night/aa-broken.fits").write_bytes(b"SIMPLE  =                    T" + b" " * 100)
    async with VirtualFileSystem({"archive": ArchiveFile(archive.url, token=archive.token)}) as vfs:
        watcher = await real_time.start(
            ImageWatcher,
            "watcher",
            watch=str(watch),
            destinations=["/archive/raw"],
            pattern="**/*.fits",
            interval=0.05,
            retry_delay=3600.0,
            max_retry_delay=3600.0,
            vfs=vfs,
        )
        await real_time.wait_for(lambda: watcher.moved == 3, PATIENCE, message="3 frames moved")
        status, body = await client.get("/frames/", ordering="DATE_OBS")
        assert status == 200
        assert [(f["basename"], f["sha256"]) for f in body["results"]] == [
            (Path(name).name, hashlib.sha256(data).hexdigest()) for name, data in frames.items()
        ]
        assert sorted(p.name for p in watch.rglob("*.fits")) == ["aa-broken.fits"]  # refused, so kept
        assert watcher.pending == 1
        await real_time.wait_for(
            lambda: "/archive/raw" in read_refusals(watch).get("night/aa-broken.fits", {}),
            PATIENCE,
            message="the refusal saved in the watcher's state",
        )
        await real_time.close()  # the watcher stops before its VFS closes


async def test_image_writer_gives_up_a_frame_the_archive_refuses_and_goes_on(
    real_time: Observatory, archive: RunningArchive, tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    (tmp_path / "refused.fits").write_bytes(fits_frame(seed=1).replace(b"INSTRUME=", b"COMMENT  "))
    (tmp_path / "good.fits").write_bytes(fits_frame(seed=2, OBJECT="good"))
    roots = {"images": LocalFile(str(tmp_path)), "archive": ArchiveFile(archive.url, token=archive.token)}
    async with VirtualFileSystem(roots) as vfs:
        # An hour's retry delay: a refusal taken for an outage would hold the good frame back.
        writer = await real_time.start(
            ImageWriter,
            "writer",
            vfs=vfs,
            pattern="/archive/{DATE-OBS}-{OBJECT}.fits",
            retry_delay=3600.0,
            max_retry_delay=3600.0,
        )
        await writer.on_new_image(NewImageEvent(filename="/images/refused.fits"), "camera")
        await writer.on_new_image(NewImageEvent(filename="/images/good.fits"), "camera")
        await real_time.wait_for(lambda: writer.waiting == 0, PATIENCE, message="both frames dealt with")
        assert len(writer.written) == 1 and writer.written[0].endswith("-good.fits")
        assert await vfs.exists("/images/refused.fits")  # the original is left where it was
        given_up = [r.getMessage() for r in caplog.records if "cannot copy" in r.getMessage()]
        assert len(given_up) == 1 and "refused the file: missing FITS keywords INSTRUME" in given_up[0]
        await real_time.close()


def read_refusals(watch: Path) -> dict[str, dict[str, str]]:
    state = json.loads((watch / ".nightcrew-watcher.json").read_text())
    return {name: entry["refused"] for name, entry in state["files"].items()}


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
