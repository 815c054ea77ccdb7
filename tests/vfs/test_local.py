"""Disk roots: symlinks kept inside the root, atomic writes, temp files hidden, modes kept."""

from __future__ import annotations

import asyncio
import os
import stat
import sys
from pathlib import Path

import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs import (
    LocalFile,
    VfsError,
    VfsFileNotFoundError,
    VfsFormatError,
    VfsPathError,
    VirtualFileSystem,
)
from nightcrew.vfs._local import TEMP_PREFIX


@pytest.fixture
def images(tmp_path: Path) -> Path:
    directory = tmp_path / "images"
    directory.mkdir()
    return directory


@pytest.fixture
def vfs(images: Path) -> VirtualFileSystem:
    return VirtualFileSystem({"cache": LocalFile(str(images))})


def _leftovers(directory: Path) -> list[str]:
    return [p.name for p in directory.rglob("*") if p.name.startswith(TEMP_PREFIX)]


async def test_files_land_in_the_root_directory(vfs: VirtualFileSystem, images: Path) -> None:
    await vfs.write_bytes("/cache/2024/a.fits", b"data")
    assert (images / "2024" / "a.fits").read_bytes() == b"data"


async def test_symlink_out_of_the_root_is_refused(
    vfs: VirtualFileSystem, images: Path, tmp_path: Path
) -> None:
    secret = tmp_path / "secret.txt"
    secret.write_text("do not read")
    (images / "link.txt").symlink_to(secret)
    (images / "outside").symlink_to(tmp_path)
    for path in ("/cache/link.txt", "/cache/outside/secret.txt"):
        with pytest.raises(VfsPathError, match=rf"^{path}: a symlink leads out of the root$"):
            await vfs.read_bytes(path)
    with pytest.raises(VfsPathError, match="a symlink leads out of the root"):
        await vfs.write_bytes("/cache/outside/new.txt", b"x")
    with pytest.raises(VfsPathError, match="a symlink leads out of the root"):
        await vfs.remove("/cache/link.txt")
    assert secret.read_text() == "do not read"
    assert not (tmp_path / "new.txt").exists()
    assert await vfs.find("/cache/**") == []  # neither the link nor the linked directory is offered


async def test_symlink_inside_the_root_is_followed(vfs: VirtualFileSystem, images: Path) -> None:
    (images / "night").mkdir()
    (images / "night" / "a.fits").write_bytes(b"a")
    (images / "latest").symlink_to(images / "night")
    (images / "alias.fits").symlink_to(images / "night" / "a.fits")
    assert await vfs.read_bytes("/cache/latest/a.fits") == b"a"
    await vfs.write_bytes("/cache/alias.fits", b"b")  # writes through the link, keeps the link
    assert (images / "alias.fits").is_symlink()
    assert (images / "night" / "a.fits").read_bytes() == b"b"
    await vfs.remove("/cache/alias.fits")  # removes the link, not its target
    assert (images / "night" / "a.fits").exists()


async def test_root_that_is_a_symlink_works(tmp_path: Path, images: Path) -> None:
    (tmp_path / "via-link").symlink_to(images)
    vfs = VirtualFileSystem({"cache": LocalFile(str(tmp_path / "via-link"))})
    await vfs.write_bytes("/cache/a.fits", b"x")
    assert (images / "a.fits").read_bytes() == b"x"


async def test_failed_replace_keeps_old_file_and_leaves_no_temp(
    vfs: VirtualFileSystem, images: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    await vfs.write_bytes("/cache/a.fits", b"old content")

    def failing_replace(src: object, dst: object) -> None:
        raise OSError(5, "Input/output error")

    monkeypatch.setattr(os, "replace", failing_replace)
    with pytest.raises(VfsError, match=r"^/cache/a\.fits: Input/output error$"):
        await vfs.write_bytes("/cache/a.fits", b"new content")
    assert (images / "a.fits").read_bytes() == b"old content"
    assert _leftovers(images) == []


async def test_crash_mid_write_keeps_old_file_and_leaves_no_temp(
    vfs: VirtualFileSystem, images: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    await vfs.write_bytes("/cache/a.fits", b"old content")

    def failing_fsync(fd: int) -> None:
        raise OSError(28, "No space left on device")  # after part of the data went to the temp file

    monkeypatch.setattr(os, "fsync", failing_fsync)
    with pytest.raises(VfsError, match="No space left on device"):
        await vfs.write_bytes("/cache/a.fits", b"new content that will not fit")
    assert (images / "a.fits").read_bytes() == b"old content"
    assert _leftovers(images) == []


async def test_value_failing_to_serialise_never_touches_the_file(
    vfs: VirtualFileSystem, images: Path
) -> None:
    await vfs.write_bytes("/cache/a.yaml", b"old: 1\n")
    with pytest.raises(VfsFormatError, match=r"^/cache/a\.yaml: cannot write YAML"):
        await vfs.write_yaml("/cache/a.yaml", {"bad": object()})
    assert (images / "a.yaml").read_bytes() == b"old: 1\n"
    assert _leftovers(images) == []


async def test_temp_files_of_writes_in_progress_are_hidden(vfs: VirtualFileSystem, images: Path) -> None:
    await vfs.write_bytes("/cache/a.fits", b"x")
    (images / f"{TEMP_PREFIX}abc").write_bytes(b"half")
    assert await vfs.listdir("/cache") == ["a.fits"]
    assert await vfs.find("/cache/*") == ["/cache/a.fits"]


async def test_replacing_keeps_the_file_mode(vfs: VirtualFileSystem, images: Path) -> None:
    await vfs.write_bytes("/cache/a.fits", b"x")
    new_mode = stat.S_IMODE((images / "a.fits").stat().st_mode)
    assert new_mode == 0o666 & ~_current_umask()  # as open() would create it, not mkstemp's 0600
    (images / "a.fits").chmod(0o640)
    await vfs.write_bytes("/cache/a.fits", b"y")
    assert stat.S_IMODE((images / "a.fits").stat().st_mode) == 0o640


def _current_umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


async def test_mkdir_creates_root_and_parents(tmp_path: Path) -> None:
    vfs = VirtualFileSystem({"cache": LocalFile(str(tmp_path / "new" / "root"))})
    assert await vfs.listdir("/cache") == []
    assert not (tmp_path / "new").exists()  # nothing created by looking
    await vfs.write_bytes("/cache/a/b/c.fits", b"x")
    assert (tmp_path / "new" / "root" / "a" / "b" / "c.fits").exists()


async def test_without_mkdir_missing_directories_are_errors(tmp_path: Path) -> None:
    vfs = VirtualFileSystem({"cache": LocalFile(str(tmp_path / "missing"), mkdir=False)})
    assert not await vfs.exists("/cache")
    with pytest.raises(VfsFileNotFoundError, match=r"^/cache/a\.fits: no such file or directory$"):
        await vfs.write_bytes("/cache/a.fits", b"x")
    with pytest.raises(VfsFileNotFoundError, match=r"^/cache: no such file or directory$"):
        await vfs.listdir("/cache")


async def test_permission_denied_is_translated(vfs: VirtualFileSystem, images: Path) -> None:
    await vfs.write_bytes("/cache/a.fits", b"x")
    (images / "a.fits").chmod(0)
    if os.geteuid() != 0:
        with pytest.raises(VfsError, match=r"^/cache/a\.fits: permission denied$"):
            await vfs.read_bytes("/cache/a.fits")
        return
    # Root ignores file permissions (CI runs as root): the read is made by a child without the
    # capabilities that override them (setpriv, util-linux).
    stdout, stderr = await _child(
        "setpriv", "--bounding-set=-dac_override,-dac_read_search", sys.executable, "-c",
        READ_WITHOUT_OVERRIDE, str(images),
    )  # fmt: skip
    assert stdout == "/cache/a.fits: permission denied\n", stderr


async def _child(*command: str) -> tuple[str, str]:
    """Run ``command`` as a child process; return what it printed and its errors."""
    child = await asyncio.create_subprocess_exec(
        *command, stdout=asyncio.subprocess.PIPE, stderr=asyncio.subprocess.PIPE
    )
    stdout, stderr = await asyncio.wait_for(child.communicate(), 60)
    return stdout.decode(), stderr.decode()


READ_WITHOUT_OVERRIDE = """
import asyncio, sys
from nightcrew.vfs import LocalFile, VfsError, VirtualFileSystem

async def main() -> None:
    async with VirtualFileSystem({"cache": LocalFile(sys.argv[1])}) as vfs:
        try:
            await vfs.read_bytes("/cache/a.fits")
        except VfsError as exc:
            print(exc)

asyncio.run(main())
"""


def test_constructor_validates_and_does_no_io(tmp_path: Path) -> None:
    LocalFile(str(tmp_path / "never" / "created"))
    assert not (tmp_path / "never").exists()
    with pytest.raises(InvalidArgumentError, match="non-empty directory path"):
        LocalFile("")


async def test_a_write_the_disk_refuses_midway_leaves_the_old_file_and_no_temp(images: Path) -> None:
    """A real failure halfway through the data: the child may write files of 64 KiB at most
    (RLIMIT_FSIZE; Python ignores SIGXFSZ, so write() fails with EFBIG after the first 64 KiB)."""
    (images / "a.fits").write_bytes(b"old content")
    stdout, stderr = await _child(sys.executable, "-c", WRITE_WITH_A_SIZE_LIMIT, str(images))
    assert stdout == "/cache/a.fits: File too large\n", stderr
    assert (images / "a.fits").read_bytes() == b"old content"
    assert _leftovers(images) == []
    assert sorted(os.listdir(images)) == ["a.fits"]


WRITE_WITH_A_SIZE_LIMIT = """
import asyncio, resource, sys
from nightcrew.vfs import LocalFile, VfsError, VirtualFileSystem

async def main() -> None:
    resource.setrlimit(resource.RLIMIT_FSIZE, (64 << 10, 64 << 10))
    async with VirtualFileSystem({"cache": LocalFile(sys.argv[1])}) as vfs:
        try:
            await vfs.write_bytes("/cache/a.fits", bytes(1 << 20))
        except VfsError as exc:
            print(exc)

asyncio.run(main())
"""
