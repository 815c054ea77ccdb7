"""HttpFileCache: a small HTTP file store for images on their way (e.g. between two machines).

Files live on disk in ``directory`` (:mod:`~nightcrew.modules.image.cache_store`): an upload is
acknowledged only once it is written atomically and flushed, so ``kill -9`` of the cache loses no
frame, and a restarted cache serves what it held. At most ``max_size`` bytes; files a consumer has
downloaded are evicted first (oldest first, or after ``max_age``), files nobody has downloaded
never: an upload that would need that is refused (507). With a ``token``, every request must carry
``Authorization: Bearer <token>``. The :class:`~nightcrew.vfs.HttpFile`
VFS root is its client. The protocol (paths are relative, URL-quoted)::

    GET    /files/<path>          the file's bytes
    PUT    /files/<path>          store the body (413 if larger than the cache)
    DELETE /files/<path>          remove the file
    GET    /meta/exists/<path>    {"result": true}        also: size, listdir, list_files,
    GET    /meta/checksum/<path>?algorithm=sha256                  checksum

Errors answer ``{"error": <VfsError class name>, "reason": <text>}`` with 404 (no such file),
400 (bad path or argument), 401 (token), 409 (other file errors), 413 (too large) or 507 (full of
files nobody has fetched yet).
"""

from __future__ import annotations

import hmac
import logging
import os
from collections.abc import Awaitable, Callable
from typing import Any

from aiohttp import web

from nightcrew.config import DataPath
from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.interfaces import ModuleState
from nightcrew.modules.image.cache_store import CacheFullError, CacheStore, TooLargeError
from nightcrew.modules.module import Module
from nightcrew.vfs import VfsError, VfsFileNotFoundError, VfsPathError

__all__ = ["FileCacheServer", "HttpFileCache", "default_directory"]

log = logging.getLogger(__name__)

_STATUS: list[tuple[type[Exception], int]] = [
    (VfsFileNotFoundError, 404),
    (VfsPathError, 400),
    (TooLargeError, 413),
    (CacheFullError, 507),
    (InvalidArgumentError, 400),
    (VfsError, 409),
]


def _error(status: int, name: str, reason: str) -> web.Response:
    return web.json_response({"error": name, "reason": reason}, status=status)


class FileCacheServer:
    """The HTTP server of the cache, usable on its own (tests) or inside :class:`HttpFileCache`.

    Args:
        host: Address to listen on.
        port: Port; 0 picks a free one (see :attr:`port` after :meth:`start`).
        directory: Where the files are kept.
        max_size: Bytes the cache holds at most.
        max_age: Wall seconds a fetched file is kept at most; None: until room is needed.
        token: Required bearer token; None: no authentication (only sensible on 127.0.0.1).
    """

    def __init__(
        self,
        *,
        host: str = "127.0.0.1",
        port: int = 0,
        directory: DataPath,
        max_size: int,
        max_age: float | None = None,
        token: str | None = None,
    ) -> None:
        self.host, self.port = host, port
        self.store = CacheStore(directory, max_size, max_age=max_age)
        self._token = token
        self._runner: web.AppRunner | None = None

    @property
    def url(self) -> str:
        return f"http://{self.host}:{self.port}"

    async def start(self) -> None:
        if self._runner is not None:
            return
        await self.store.load()
        # Bodies up to the cache size: aiohttp refuses more than 1 MiB by default.
        app = web.Application(client_max_size=self.store.max_size + 1, middlewares=[self._authenticate])
        app.router.add_get("/files/{path:.*}", self._get)
        app.router.add_put("/files/{path:.*}", self._put)
        app.router.add_delete("/files/{path:.*}", self._delete)
        app.router.add_get("/meta/{op}/{path:.*}", self._meta)
        runner = web.AppRunner(app, access_log=None)
        await runner.setup()
        try:
            await web.TCPSite(runner, self.host, self.port).start()
        except OSError:
            await runner.cleanup()
            raise
        self._runner = runner
        self.port = runner.addresses[0][1]

    async def stop(self) -> None:
        """Stop serving; safe to call twice."""
        runner, self._runner = self._runner, None
        if runner is not None:
            await runner.cleanup()

    @web.middleware
    async def _authenticate(
        self, request: web.Request, handler: Callable[[web.Request], Awaitable[web.StreamResponse]]
    ) -> web.StreamResponse:
        if self._token is not None:
            given = request.headers.get("Authorization", "")
            if not hmac.compare_digest(given.encode(), f"Bearer {self._token}".encode()):
                return _error(401, "VfsError", "permission denied: wrong or missing token")
        try:
            return await handler(request)
        except (VfsError, InvalidArgumentError) as exc:
            status = next(code for kind, code in _STATUS if isinstance(exc, kind))
            reason = exc.reason if isinstance(exc, VfsError) else exc.message
            name = "VfsError" if isinstance(exc, TooLargeError | CacheFullError) else type(exc).__name__
            return _error(status, name, reason)

    async def _get(self, request: web.Request) -> web.Response:
        path = request.match_info["path"]
        response = web.Response(body=await self.store.read(path))
        # Fetched only once the consumer has the bytes: a download cut short keeps the file safe.
        await response.prepare(request)
        await response.write_eof()
        try:
            await self.store.mark_fetched(path)
        except VfsError as exc:  # the file then counts as not fetched: kept longer, never lost
            log.warning("file cache: cannot note that %s was fetched: %s", path, exc)
        return response

    async def _put(self, request: web.Request) -> web.Response:
        evicted = await self.store.write(request.match_info["path"], await request.read())
        if evicted:
            log.info(
                "file cache: evicted %d fetched files (size limit or max_age): %s", len(evicted), evicted
            )
        return web.Response(status=204)

    async def _delete(self, request: web.Request) -> web.Response:
        await self.store.remove(request.match_info["path"])
        return web.Response(status=204)

    async def _meta(self, request: web.Request) -> web.Response:
        path, op, root = request.match_info["path"], request.match_info["op"], self.store.root
        result: Any
        if op == "exists":
            result = await root.exists(path)
        elif op == "size":
            result = await root.size(path)
        elif op == "listdir":
            result = await root.listdir(path)
        elif op == "list_files":
            result = await root.list_files(path)
        elif op == "checksum":
            result = await root.checksum(path, request.query.get("algorithm", "sha256"))
        else:
            return _error(404, "VfsError", f"unknown operation {op!r}")
        return web.json_response({"result": result})


class HttpFileCache(Module):
    """Runs a :class:`FileCacheServer` as a module.

    Args:
        host: Address to listen on (127.0.0.1: this machine only).
        port: Port; 0 picks a free one.
        directory: Where the files are kept (made at start); default
            ``$XDG_STATE_HOME/nightcrew/<module name>`` (``~/.local/state/...``).
        max_size: Bytes the cache holds at most, > 0 (fetched files evicted first, oldest first).
        max_age: Wall seconds a fetched file is kept at most, > 0; None: until room is needed.
        token: Bearer token every request must carry; None: none (only on 127.0.0.1).
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        host: str = "127.0.0.1",
        port: int = 37081,
        directory: str | None = None,
        max_size: int = 1 << 30,
        max_age: float | None = None,
        token: str | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not max_size > 0:
            raise ConfigError(f"must be > 0 bytes, got {max_size}", key="max_size")
        if max_age is not None and not max_age > 0:
            raise ConfigError(f"must be > 0 seconds (or left out), got {max_age}", key="max_age")
        if directory is not None and (not isinstance(directory, str) or not directory):
            raise ConfigError("must be a directory path", key="directory")
        if not 0 <= port < 65536:
            raise ConfigError(f"must be a port number (0 picks a free one), got {port}", key="port")
        if token is None and host not in ("127.0.0.1", "localhost", "::1"):
            raise ConfigError(f"a cache listening on {host} needs a token", key="token")
        if token is not None and len(token) < 8:
            raise ConfigError("use a token of at least 8 characters", key="token")
        self.server = FileCacheServer(
            host=host,
            port=port,
            directory=os.path.abspath(directory or default_directory(self.name)),
            max_size=max_size,
            max_age=max_age,
            token=token,
        )

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await self.server.start()
        try:
            await super().open()
        except BaseException:
            await self.server.stop()
            raise
        log.info("%s: file cache at %s, files in %s", self.name, self.server.url, self.server.store.directory)

    async def close(self) -> None:
        await super().close()
        await self.server.stop()


def default_directory(name: str) -> str:
    """``$XDG_STATE_HOME/nightcrew/<name>``, else ``~/.local/state/nightcrew/<name>``."""
    state = os.environ.get("XDG_STATE_HOME") or os.path.join(os.path.expanduser("~"), ".local", "state")
    return os.path.join(state, "nightcrew", name)
