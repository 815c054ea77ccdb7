"""A VFS root on an HTTP file cache (:class:`nightcrew.modules.image.HttpFileCache`).

Every FileRoot method is one HTTP request (protocol in that module's docstring); errors come back
as the same VfsError classes with the same reasons, so the root behaves like a local one. Paths
are normalised here before they travel. Checksums are computed by the server, so verifying a
copy does not download it.
"""

from __future__ import annotations

from typing import Any
from urllib.parse import quote

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs._errors import (
    UnknownRootError,
    VfsError,
    VfsFileNotFoundError,
    VfsFormatError,
    VfsPathError,
)
from nightcrew.vfs._http_client import HttpClientRoot
from nightcrew.vfs._paths import normalise_relative
from nightcrew.vfs._root import new_hash

__all__ = ["HttpFile"]

_ERRORS: dict[str, type[VfsError]] = {
    cls.__name__: cls
    for cls in (VfsError, VfsPathError, UnknownRootError, VfsFileNotFoundError, VfsFormatError)
}


class HttpFile(HttpClientRoot):
    """Files on an HTTP file cache.

    Args:
        url: The cache's address, e.g. ``http://127.0.0.1:37081``.
        token: Its bearer token, if it has one.
        timeout: Wall seconds one request may take.
    """

    server_name = "the file cache"

    def __init__(self, url: str, *, token: str | None = None, timeout: float = 60.0) -> None:
        super().__init__(url, token=token, timeout=timeout)

    async def _request(
        self,
        method: str,
        route: str,
        path: str,
        *,
        data: bytes | None = None,
        params: dict[str, str] | None = None,
    ) -> bytes:
        relative = normalise_relative(path)
        url = f"{self.url}/{route}/{quote(relative)}"
        status, body = await self._send(method, url, relative, data=data, params=params)
        if status >= 400:
            raise _error(status, body, relative)
        return body

    async def _meta(self, op: str, path: str, params: dict[str, str] | None = None) -> Any:
        import json

        return json.loads(await self._request("GET", f"meta/{op}", path, params=params))["result"]

    async def read_bytes(self, path: str) -> bytes:
        return await self._request("GET", "files", path)

    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        await self._request("PUT", "files", path, data=bytes(data))

    async def exists(self, path: str) -> bool:
        return bool(await self._meta("exists", path))

    async def listdir(self, path: str) -> list[str]:
        return list(await self._meta("listdir", path))

    async def remove(self, path: str) -> None:
        await self._request("DELETE", "files", path)

    async def size(self, path: str) -> int:
        return int(await self._meta("size", path))

    async def list_files(self, under: str = "") -> list[str]:
        return list(await self._meta("list_files", under))

    async def checksum(self, path: str, algorithm: str = "sha256") -> str:
        new_hash(algorithm)  # an unknown algorithm fails here, with the local error
        return str(await self._meta("checksum", path, {"algorithm": algorithm}))


def _error(status: int, body: bytes, path: str) -> Exception:
    """The error the server described, as the same class with the same reason."""
    import json

    try:
        described = json.loads(body)
        name, reason = str(described["error"]), str(described["reason"])
    except (ValueError, KeyError, TypeError):  # not our server's answer, e.g. its size limit
        what = "larger than the file cache" if status == 413 else "file cache refused it"
        return VfsError(f"{what} (HTTP {status})", path=path)
    if name == "InvalidArgumentError":
        return InvalidArgumentError(reason)
    return _ERRORS.get(name, VfsError)(reason, path=path)
