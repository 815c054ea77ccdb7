"""Faults shared by the SSH and SMB root tests: a server restarted under a root, and a write cut
off by a server that dies under it."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from nightcrew.vfs import FileRoot, VfsError, VirtualFileSystem

#: Large enough that the copy is still under way when the server is stopped.
BIG = 96 << 20
_WAIT = 60.0  # wall seconds any single wait may take (a busy machine)


def temp_files(directory: Path) -> list[Path]:
    return [p for p in directory.iterdir() if p.name.startswith(".nightcrew-tmp-")]


async def wait_until(condition: Callable[[], bool], what: str) -> None:
    """Poll ``condition`` until it holds, at most _WAIT wall seconds."""
    deadline = time.monotonic() + _WAIT
    while not condition():
        assert time.monotonic() < deadline, f"{what}: not within {_WAIT:g} s"
        await asyncio.sleep(0.001)


async def reconnects_after_the_server_restarts(
    root: FileRoot, server: str, stop: Callable[[], None], start: Callable[[], None]
) -> None:
    """``root`` fails naming the ``server`` (a regex) while it is down, and works again once it is
    back, also when the connection looked alive when it went."""
    async with VirtualFileSystem({"remote": root}) as vfs:
        await vfs.write_bytes("/remote/a.fits", b"1")
        stop()
        with pytest.raises(
            VfsError, match=rf"^/remote/a\.fits: (cannot reach|lost the connection to) {server}"
        ):
            await vfs.read_bytes("/remote/a.fits")
        start()
        assert await vfs.read_bytes("/remote/a.fits") == b"1"
        stop()  # and once more while the connection is idle and thought alive
        start()
        await vfs.write_bytes("/remote/b.fits", b"2")  # the lost link is noticed and replaced
        assert await vfs.listdir("/remote") == ["a.fits", "b.fits"]


async def write_cut_off_by_a_dead_server(
    root: FileRoot, directory: Path, stop: Callable[[], None], start: Callable[[], None]
) -> int:
    """Stop the server while ``root`` writes a big file over an old one; check nothing half-written
    shows, and that after a restart the same root writes it. Returns the bytes on the server's disk
    in the orphaned temporary file when the server stopped. Closes ``root``."""
    try:
        return await _write_cut_off(root, directory, stop, start)
    finally:
        await root.close()


async def _write_cut_off(
    root: FileRoot, directory: Path, stop: Callable[[], None], start: Callable[[], None]
) -> int:
    await root.write_bytes("night/a.fits", b"old content")
    target = directory / "night" / "a.fits"
    new = bytes(range(256)) * (BIG // 256)
    writing = asyncio.create_task(root.write_bytes("night/a.fits", new))

    def part_written() -> bool:
        assert not writing.done(), "the write finished before the server could be stopped: make BIG larger"
        return any(p.stat().st_size > 0 for p in temp_files(target.parent))

    await wait_until(part_written, "a temporary file with data")
    stop()
    with pytest.raises(
        VfsError, match=r"night/a\.fits: (lost the connection|cannot reach|SSH server|SMB server)"
    ):
        await writing
    assert target.read_bytes() == b"old content"  # never half of the new one
    orphans = temp_files(target.parent)
    written = sum(p.stat().st_size for p in orphans)
    assert written < len(new)
    start()
    assert await root.listdir("night") == ["a.fits"]  # an orphaned temporary file stays hidden
    await root.write_bytes("night/a.fits", new)
    assert target.read_bytes() == new
    return written
