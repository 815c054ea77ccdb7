"""What differs between roots: MemoryFile sharing by name, TempFile cleanup."""

from __future__ import annotations

import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs import MemoryFile, TempFile, VfsError, VirtualFileSystem


async def test_named_memory_files_share_one_store() -> None:
    camera = VirtualFileSystem({"cache": MemoryFile("shared")})
    writer = VirtualFileSystem({"incoming": MemoryFile("shared")})
    await camera.write_bytes("/cache/img.fits", b"photons")
    assert await writer.read_bytes("/incoming/img.fits") == b"photons"
    await camera.close()  # closing one user keeps the shared store for the others
    assert await writer.exists("/incoming/img.fits")


async def test_unnamed_memory_files_are_private() -> None:
    first, second = MemoryFile(), MemoryFile()
    await first.write_bytes("img.fits", b"photons")
    assert not await second.exists("img.fits")
    await first.close()
    assert not await first.exists("img.fits")


async def test_clear_shared_forgets_one_or_all_stores() -> None:
    a, b = MemoryFile("a"), MemoryFile("b")
    await a.write_bytes("x", b"1")
    await b.write_bytes("x", b"2")
    MemoryFile.clear_shared("a")
    assert not await a.exists("x")
    assert await b.exists("x")
    MemoryFile.clear_shared()
    assert not await b.exists("x")


def test_memory_file_name_must_not_be_empty() -> None:
    with pytest.raises(InvalidArgumentError, match="name must not be empty"):
        MemoryFile("")


async def test_temp_file_creates_its_directory_lazily_and_removes_it_on_close() -> None:
    root = TempFile(prefix="nightcrew-cleanup-")
    assert [root.directory] == [None]  # constructor did no I/O (a list: mypy would narrow the property)
    await root.write_bytes("night/a.fits", b"x")
    directory = root.directory
    assert directory is not None
    assert directory.name.startswith("nightcrew-cleanup-")
    assert (directory / "night" / "a.fits").read_bytes() == b"x"
    await root.close()
    assert not directory.exists()
    await root.close()  # safe twice


async def test_temp_file_refuses_use_after_close() -> None:
    root = TempFile()
    await root.close()
    with pytest.raises(VfsError, match="TempFile is closed"):
        await root.write_bytes("a.fits", b"x")


async def test_vfs_close_closes_its_roots() -> None:
    root = TempFile()
    async with VirtualFileSystem({"tmp": root}) as vfs:
        await vfs.write_bytes("/tmp/a.fits", b"x")
        directory = root.directory
    assert directory is not None
    assert not directory.exists()
    await vfs.close()  # safe twice


def test_temp_file_prefix_must_be_a_name() -> None:
    with pytest.raises(InvalidArgumentError, match="prefix must be a plain name"):
        TempFile(prefix="../evil")
