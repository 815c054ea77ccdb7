"""HttpFileCache: upload, download, eviction of the oldest and token auth, over real HTTP."""

from __future__ import annotations

import aiohttp
import pytest

from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.modules.image.http_cache import HttpFileCache
from nightcrew.testing import Observatory
from nightcrew.vfs import HttpFile, VfsError, VfsFileNotFoundError, VirtualFileSystem

TOKEN = "s3cret-token"


async def test_upload_download_evict_and_auth(fast_observatory: Observatory) -> None:
    cache = await fast_observatory.start(HttpFileCache, "filecache", port=0, max_size=10_000, token=TOKEN)
    url = cache.server.url
    auth = {"Authorization": f"Bearer {TOKEN}"}
    async with aiohttp.ClientSession() as session:
        async with session.put(f"{url}/files/night/a.fits", data=b"a" * 4000, headers=auth) as response:
            assert response.status == 204
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

    # Through the VFS: b and c fit beside a; d pushes the total over 10 kB, so a (oldest) goes.
    async with VirtualFileSystem({"remote": HttpFile(url, token=TOKEN)}) as vfs:
        await vfs.write_bytes("/remote/night/b.fits", b"b" * 3000)
        await vfs.write_bytes("/remote/night/c.fits", b"c" * 2000)
        await vfs.write_bytes("/remote/night/a.fits", b"A" * 4000)  # rewritten: now the newest
        await vfs.write_bytes("/remote/night/d.fits", b"d" * 2500)
        assert await vfs.listdir("/remote/night") == ["a.fits", "c.fits", "d.fits"]
        assert cache.server.store.total == 8500 and cache.server.store.evicted == 1
        assert await vfs.read_bytes("/remote/night/a.fits") == b"A" * 4000
        with pytest.raises(VfsFileNotFoundError, match=r"^/remote/night/b\.fits: no such file"):
            await vfs.read_bytes("/remote/night/b.fits")
        with pytest.raises(
            VfsError, match=r"^/remote/huge\.fits: 10001 bytes exceed the cache size of 10000"
        ):
            await vfs.write_bytes("/remote/huge.fits", b"h" * 10_001)
        with pytest.raises(VfsError, match=r"^/remote/huge\.fits: larger than the file cache \(HTTP 413\)"):
            await vfs.write_bytes("/remote/huge.fits", b"h" * 20_000)  # refused by aiohttp's body limit


@pytest.mark.parametrize(
    ("options", "key", "message"),
    [
        ({"host": "0.0.0.0"}, "token", "needs a token"),
        ({"token": "short"}, "token", "at least 8 characters"),
        ({"max_size": 0}, "max_size", "must be > 0 bytes"),
    ],
)
def test_config_errors_name_the_key(options: dict[str, object], key: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message) as info:
        build_object({"class": "nightcrew.modules.image.http_cache.HttpFileCache", "name": "c", **options})
    assert info.value.key == key
