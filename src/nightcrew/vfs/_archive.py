"""A VFS root on the image archive (``nightcrew archive``, :mod:`nightcrew.services.archive`).

Writing a file uploads it: the archive checks it (a complete FITS file with DATE-OBS, INSTRUME,
IMAGETYP, EXPTIME) and files it by its header under ``<DAY-OBS>/<INSTRUME>/<basename>``, so the
directories of the written path do not matter; every path is resolved by its last component,
the frame's basename, which the archive keeps unique. Reading, listing, sizes and checksums come
from the archive's API; the sha256 checksum is the one the archive computed from the bytes it
stored, so a copy is verified without downloading it back. Uploading a file the archive already
holds (same sha256) succeeds: a retried copy is not an error. The archive keeps its frames:
:meth:`ArchiveFile.remove` is refused. Listing walks the whole index page by page.
"""

from __future__ import annotations

import io
import json
import posixpath
from typing import Any

from nightcrew.vfs._errors import VfsError, VfsFileNotFoundError, VfsFormatError
from nightcrew.vfs._http_client import HttpClientRoot
from nightcrew.vfs._paths import normalise_relative
from nightcrew.vfs._root import new_hash

__all__ = ["ArchiveFile"]

_PAGE = 1000
_REFUSED_CONTENT = (400, 413, 415, 422)


class ArchiveFile(HttpClientRoot):
    """Frames in an image archive.

    Args:
        url: The archive's address, e.g. ``http://127.0.0.1:37190``.
        token: Its upload token (needed for writing only); ``${NIGHTCREW_ARCHIVE_TOKEN}`` in YAML.
        timeout: Wall seconds one request may take.
    """

    server_name = "the archive"

    def __init__(self, url: str, *, token: str | None = None, timeout: float = 120.0) -> None:
        super().__init__(url, token=token, timeout=timeout)

    async def _request(
        self,
        method: str,
        url: str,
        path: str,
        *,
        data: io.BytesIO | None = None,
        params: dict[str, str] | None = None,
    ) -> tuple[int, bytes]:
        # The token is an upload token: sent with uploads only.
        return await self._send(method, url, path, data=data, params=params, authorised=data is not None)

    async def _frame(self, path: str) -> dict[str, Any]:
        """The archive's record of the frame at ``path`` (by basename)."""
        relative = normalise_relative(path)
        basename = posixpath.basename(relative)
        if not basename:
            raise VfsFileNotFoundError("the archive's root is not a file", path=relative)
        status, body = await self._request(
            "GET", f"{self.url}/frames/", relative, params={"basename": basename}
        )
        if status != 200:
            raise _error(status, body, relative)
        results = json.loads(body)["results"]
        if not results:
            raise VfsFileNotFoundError("no such frame in the archive", path=relative)
        frame: dict[str, Any] = results[0]
        return frame

    async def _all_frames(self) -> list[dict[str, Any]]:
        frames: list[dict[str, Any]] = []
        url: str | None = f"{self.url}/frames/?ordering=id&limit={_PAGE}"
        while url is not None:
            status, body = await self._request("GET", url, "")
            if status != 200:
                raise _error(status, body, "")
            page = json.loads(body)
            frames += page["results"]
            url = page["next"]
        return frames

    async def read_bytes(self, path: str) -> bytes:
        frame = await self._frame(path)
        status, body = await self._request("GET", frame["url"], path)
        if status != 200:
            raise _error(status, body, normalise_relative(path))
        return body

    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        relative = normalise_relative(path)
        params = {"filename": posixpath.basename(relative)}
        # A file object, not bytes: aiohttp warns that a large bytes body blocks the event loop.
        status, body = await self._request(
            "POST", f"{self.url}/frames/upload/", relative, data=io.BytesIO(data), params=params
        )
        if status == 201:
            return
        if status == 409 and _json(body).get("duplicate") is True:
            return  # the archive holds exactly these bytes already
        raise _error(status, body, relative)

    async def exists(self, path: str) -> bool:
        relative = normalise_relative(path)
        if relative == "":
            return True
        try:
            await self._frame(relative)
            return True
        except VfsFileNotFoundError:
            return any(name.startswith(relative + "/") for name in await self.list_files())

    async def listdir(self, path: str) -> list[str]:
        relative = normalise_relative(path)
        prefix = relative + "/" if relative else ""
        names = {
            name[len(prefix) :].split("/")[0] for name in await self.list_files() if name.startswith(prefix)
        }
        if not names and relative:
            raise VfsFileNotFoundError("no such directory in the archive", path=relative)
        return sorted(names)

    async def remove(self, path: str) -> None:
        raise VfsError(
            "the archive keeps its frames: removing is not supported", path=normalise_relative(path)
        )

    async def size(self, path: str) -> int:
        return int((await self._frame(path))["size"])

    async def list_files(self, under: str = "") -> list[str]:
        relative = normalise_relative(under)
        prefix = relative + "/" if relative else ""
        return sorted(str(f["path"]) for f in await self._all_frames() if str(f["path"]).startswith(prefix))

    async def checksum(self, path: str, algorithm: str = "sha256") -> str:
        digest = new_hash(algorithm)  # an unknown algorithm fails here, with the local error
        if digest.name == "sha256":
            return str((await self._frame(path))["sha256"])
        digest.update(await self.read_bytes(path))
        return digest.hexdigest()


def _json(body: bytes) -> dict[str, Any]:
    try:
        parsed = json.loads(body)
    except ValueError:
        return {}
    return parsed if isinstance(parsed, dict) else {}


def _error(status: int, body: bytes, path: str) -> VfsError:
    """The archive's refusal as a VfsError with its message."""
    detail = str(_json(body).get("detail") or f"HTTP {status}")
    if status == 404:
        return VfsFileNotFoundError(f"the archive: {detail}", path=path)
    if status in _REFUSED_CONTENT:
        return VfsFormatError(f"the archive refused the file: {detail}", path=path)
    return VfsError(f"the archive answered {status}: {detail}", path=path)
