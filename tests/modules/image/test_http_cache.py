"""HttpFileCache over real HTTP: upload, download, token auth; files on disk that a restarted cache
serves; eviction that drops fetched files only (oldest first, or by age), never an unfetched one."""

from __future__ import annotations

import os
import time
from pathlib import Path

import aiohttp
import pytest

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.modules.image.http_cache import HttpFileCache, default_directory
from nightcrew.testing import Observatory
from nightcrew.vfs import HttpFile, VfsError, VfsFileNotFoundError, VirtualFileSystem

TOKEN = "s3cret-token"


async def test_upload_download_and_auth(fast_observatory: Observatory, tmp_path: Path) -> None:
    cache = await fast_observatory.start(
        HttpFileCache, "filecache", port=0, directory=str(tmp_path), max_size=10_000, token=TOKEN
    )
    url = cache.server.url
    auth = {"Authorization": f"Bearer {TOKEN}"}
    async with aiohttp.ClientSession() as session:
        async with session.put(f"{url}/files/night/a.fits", data=b"a" * 4000, headers=auth) as response:
            assert response.status == 204
        assert (
            tmp_path / "files" / "night" / "a.fits"
        ).read_bytes() == b"a" * 4000  # on disk when acknowledged
        async with session.get(f"{url}/files/night/a.fits", headers=auth) as response:
            assert response.status == 200 and await response.read() == b"a" * 4000
        async with session.get(f"{url}/files/night/a.fits") as response:
            assert response.status == 401
            assert await response.json() == {
                "error": "VfsError",
                "reason": "permission denied: wrong or missing token",
            }
        async with session.get(f"{url}/files/night/b.fits", headers=auth) as response:
            assert response.status == 404 and (await response.json())["error"] == "VfsFileNotFoundError"
        async with session.put(f"{url}/files/big.fits", data=b"x" * 10_001, headers=auth) as response:
            assert response.status == 413
    async with VirtualFileSystem({"remote": HttpFile(url, token=TOKEN)}) as vfs:
        with pytest.raises(
            VfsError, match=r"^/remote/huge\.fits: 10001 bytes exceed the cache size of 10000"
        ):
            await vfs.write_bytes("/remote/huge.fits", b"h" * 10_001)
        with pytest.raises(VfsError, match=r"^/remote/huge\.fits: larger than the file cache \(HTTP 413\)"):
            await vfs.write_bytes("/remote/huge.fits", b"h" * 20_000)  # refused by aiohttp's body limit


async def test_only_fetched_files_are_evicted(fast_observatory: Observatory, tmp_path: Path) -> None:
    cache = await fast_observatory.start(
        HttpFileCache, "filecache", port=0, directory=str(tmp_path), max_size=10_000, token=TOKEN
    )
    async with VirtualFileSystem({"remote": HttpFile(cache.server.url, token=TOKEN)}) as vfs:
        await vfs.write_bytes("/remote/night/a.fits", b"a" * 4000)
        await vfs.write_bytes("/remote/night/b.fits", b"b" * 3000)
        await vfs.write_bytes("/remote/night/c.fits", b"c" * 2000)
        # Nobody has fetched a, b or c: there is no room for d, and none of them is dropped.
        with pytest.raises(
            VfsError,
            match=r"^/remote/night/d\.fits: the file cache is full: 3 files \(9000 bytes in all\) wait for",
        ):
            await vfs.write_bytes("/remote/night/d.fits", b"d" * 2500)
        assert not (tmp_path / "files" / "night" / "d.fits").exists()
        # b and c are fetched (listing and checksums do not count); the older of them, b, goes.
        assert await vfs.read_bytes("/remote/night/c.fits") == b"c" * 2000
        assert await vfs.read_bytes("/remote/night/b.fits") == b"b" * 3000
        await vfs.checksum("/remote/night/a.fits")
        await vfs.write_bytes("/remote/night/d.fits", b"d" * 2500)
        assert await vfs.listdir("/remote/night") == ["a.fits", "c.fits", "d.fits"]
        assert cache.server.store.total == 8500 and cache.server.store.evicted == 1
        with pytest.raises(VfsFileNotFoundError, match=r"^/remote/night/b\.fits: no such file"):
            await vfs.read_bytes("/remote/night/b.fits")
        # Rewriting c makes it new and unfetched again; a removed file frees its room.
        await vfs.write_bytes("/remote/night/c.fits", b"C" * 2000)
        await vfs.remove("/remote/night/a.fits")
        await vfs.write_bytes("/remote/night/e.fits", b"e" * 5000)
        assert await vfs.listdir("/remote/night") == ["c.fits", "d.fits", "e.fits"]
        assert cache.server.store.unfetched == 3


async def test_a_restarted_cache_serves_what_is_on_disk(
    fast_observatory: Observatory, tmp_path: Path
) -> None:
    options = {"port": 0, "directory": str(tmp_path), "max_size": 10_000, "max_age": 600.0, "token": TOKEN}
    first = await fast_observatory.start(HttpFileCache, "filecache", **options)
    async with VirtualFileSystem({"remote": HttpFile(first.server.url, token=TOKEN)}) as vfs:
        for name in ("old", "kept", "unfetched"):
            await vfs.write_bytes(f"/remote/{name}.fits", name.encode() * 100)
        await vfs.read_bytes("/remote/old.fits")
        await vfs.read_bytes("/remote/kept.fits")
    await first.close()
    # What a kill -9 leaves: a write cut short; and "old" and "unfetched" written two hours ago.
    (tmp_path / "files" / ".nightcrew-tmp-cut-short").write_bytes(b"half a frame")
    two_hours_ago = time.time() - 7200
    for name in ("old", "unfetched"):
        os.utime(tmp_path / "files" / f"{name}.fits", (two_hours_ago, two_hours_ago))

    second = await fast_observatory.start(HttpFileCache, "filecache2", **options)
    assert not (tmp_path / "files" / ".nightcrew-tmp-cut-short").exists()
    assert second.server.store.total == 300 + 400 + 900 and second.server.store.unfetched == 1
    async with VirtualFileSystem({"remote": HttpFile(second.server.url, token=TOKEN)}) as vfs:
        assert await vfs.read_bytes("/remote/kept.fits") == b"kept" * 100
        # The next upload drops what was fetched more than max_age ago; the unfetched one stays.
        await vfs.write_bytes("/remote/new.fits", b"n" * 10)
        assert await vfs.listdir("/remote") == ["kept.fits", "new.fits", "unfetched.fits"]
        assert await vfs.read_bytes("/remote/unfetched.fits") == b"unfetched" * 100


def test_the_default_directory_is_the_modules_state_directory(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_STATE_HOME", "/srv/state")
    assert default_directory("cache") == "/srv/state/nightcrew/cache"
    monkeypatch.delenv("XDG_STATE_HOME")
    monkeypatch.setenv("HOME", "/home/observer")
    cache = build_object({"class": "nightcrew.modules.image.http_cache.HttpFileCache", "name": "cache"})
    assert isinstance(cache, HttpFileCache)
    assert str(cache.server.store.directory) == "/home/observer/.local/state/nightcrew/cache"


@pytest.mark.parametrize(
    ("options", "key", "message"),
    [
        ({"host": "0.0.0.0"}, "token", "needs a token"),
        ({"token": "short"}, "token", "at least 8 characters"),
        ({"max_size": 0}, "max_size", "must be > 0 bytes"),
        ({"max_age": 0}, "max_age", "must be > 0 seconds"),
        ({"directory": ""}, "directory", "must be a directory path"),
    ],
)
def test_config_errors_name_the_key(options: dict[str, object], key: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message) as info:
        build_object({"class": "nightcrew.modules.image.http_cache.HttpFileCache", "name": "c", **options})
    assert info.value.key == key
