"""The VFS contract suite on an HttpFile root backed by a real HttpFileCache server on 127.0.0.1.

The contract tests are imported from test_contract and run here with this module's ``root``.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from nightcrew.modules.image.http_cache import FileCacheServer
from nightcrew.vfs import FileRoot, HttpFile, VfsError, VirtualFileSystem
from tests.vfs.test_contract import *  # noqa: F403 - every contract test, run on this root

TOKEN = "contract-secret"


@pytest.fixture
async def server(tmp_path: Path) -> AsyncIterator[FileCacheServer]:
    cache = FileCacheServer(directory=str(tmp_path / "cache"), max_size=1 << 24, token=TOKEN)
    await cache.start()
    try:
        yield cache
    finally:
        await cache.stop()


@pytest.fixture
async def root(server: FileCacheServer) -> AsyncIterator[FileRoot]:
    http_root = HttpFile(server.url, token=TOKEN)
    try:
        yield http_root
    finally:
        await http_root.close()


async def test_a_wrong_token_is_refused(server: FileCacheServer) -> None:
    async with VirtualFileSystem({"cache": HttpFile(server.url, token="wrong")}) as vfs:
        with pytest.raises(VfsError, match=r"^/cache/a\.fits: permission denied: wrong or missing token"):
            await vfs.write_bytes("/cache/a.fits", b"x")


async def test_an_unreachable_cache_is_a_vfs_error(server: FileCacheServer) -> None:
    url = server.url
    await server.stop()
    async with VirtualFileSystem({"cache": HttpFile(url, token=TOKEN, timeout=5)}) as vfs:
        with pytest.raises(
            VfsError, match=r"^/cache/a\.fits: cannot reach the file cache at http://127\.0\.0\.1"
        ):
            await vfs.read_bytes("/cache/a.fits")
