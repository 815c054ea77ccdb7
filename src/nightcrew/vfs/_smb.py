"""A VFS root on an SMB share (Samba, Windows), through smbprotocol's ``smbclient``.

Chosen: smbprotocol, the maintained pure-Python SMB 2/3 client; its ``smbclient`` API mirrors
``os`` and ``open`` (errors are ``OSError`` subclasses with the usual errno). It blocks, so every
call runs in a worker thread, in the ``_blocking_*`` functions below (through
:func:`~nightcrew.vfs._root.in_thread`, which leaves smbprotocol's chatty log out of the module's).

* **Login** by user name and password (NTLM), on the server's port (445 by default).
* **Reconnect.** The root keeps its own connection cache (not smbclient's process-wide one).
  When the connection is lost the operation that noticed it is tried once more on a fresh one —
  all operations are idempotent except :meth:`SMBFile.remove`, which is not retried — and if that
  fails too it raises :class:`VfsError` naming the server. smbclient has no per-operation timeout
  (it waits on a silent link for many minutes), so each operation is bounded here by ``timeout``:
  then the connection's socket is shut, which ends the waiting thread, and the next call connects
  anew.
* **Atomic writes.** Data goes to a hidden temporary file (``.nightcrew-tmp-…``) beside the
  target and is renamed over it with "replace if exists" (one SMB2 SET_INFO; Samba renames with
  ``rename(2)``): a reader, or a copy cut off by a dead server, sees the old file or the new one.
  A temporary file orphaned by a lost connection is hidden from ``listdir``/``find``.
"""

from __future__ import annotations

import asyncio
import contextlib
import errno
import secrets
import stat
from collections.abc import Callable, Iterator
from functools import partial
from typing import Any, TypeVar

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs._errors import VfsError, VfsFileNotFoundError
from nightcrew.vfs._local import TEMP_PREFIX
from nightcrew.vfs._paths import normalise_relative
from nightcrew.vfs._root import FileRoot, in_thread, new_hash

__all__ = ["SMBFile"]

_T = TypeVar("_T")
_CHUNK_BYTES = 1 << 20
_CLOSE_TIMEOUT = 5.0
#: NT statuses smbclient reports when the share does not exist: BAD_NETWORK_NAME, and NOT_FOUND
#: after it has looked for the name in DFS as well.
_NO_SHARE = (0xC00000CC, 0xC0000225)


class _LoginError(Exception):
    """Connecting or logging in failed (kept apart from a lost connection: not retried)."""

    def __init__(self, message: str, *, refused: bool) -> None:
        super().__init__(message)
        self.refused = refused  # the server answered and refused the account


class SMBFile(FileRoot):
    """Files in a directory of an SMB share.

    Args:
        host: The server's name or address.
        share: The share's name (``images`` in ``\\\\host\\images``).
        username: Login name.
        password: Its password (in YAML, ``${SMB_PASSWORD}`` from the environment).
        root: Directory inside the share holding the files (``raw/2026``); the share itself if "".
        port: The server's port.
        connect_timeout: Wall seconds a connection (with login) may take.
        timeout: Wall seconds one operation may take.
        mkdir: Create missing directories when writing.
    """

    def __init__(
        self,
        host: str,
        *,
        share: str,
        username: str,
        password: str,
        root: str = "",
        port: int = 445,
        connect_timeout: float = 15.0,
        timeout: float = 60.0,
        mkdir: bool = True,
    ) -> None:
        for name, value in (("host", host), ("share", share), ("username", username)):
            if not isinstance(value, str) or not value or "\\" in value or "/" in value:
                raise InvalidArgumentError(f"SMBFile {name} must be a plain non-empty name, got {value!r}")
        if not isinstance(password, str):
            raise InvalidArgumentError("SMBFile password must be a string")
        if not isinstance(port, int) or not 0 < port < 65536:
            raise InvalidArgumentError(f"SMBFile port must be 1..65535, got {port!r}")
        if not connect_timeout > 0 or not timeout > 0:
            raise InvalidArgumentError("SMBFile connect_timeout and timeout must be > 0 seconds")
        self.host, self.share, self.username, self.port = host, share, username, port
        self.root = normalise_relative(root)
        self._password = password
        self._connect_timeout, self._timeout = float(connect_timeout), float(timeout)
        self.mkdir = mkdir
        self._cache: dict[str, Any] = {}  # smbclient's connection cache, this root's own

    @property
    def server(self) -> str:
        """``user@host:port/share``, as errors name the server."""
        return f"{self.username}@{self.host}:{self.port}/{self.share}"

    def __repr__(self) -> str:
        return f"SMBFile({self.server!r}, root={self.root!r})"

    def _unc(self, relative: str) -> str:
        parts = [part for part in (self.root, relative) if part]
        inside = "\\".join(parts).replace("/", "\\")
        return f"\\\\{self.host}\\{self.share}" + (f"\\{inside}" if inside else "")

    def _options(self, cache: dict[str, Any]) -> dict[str, Any]:
        return {
            "username": self.username,
            "password": self._password,
            "port": self.port,
            "connection_cache": cache,
        }

    # --- the connection ------------------------------------------------------------------------

    def _blocking_session(self, cache: dict[str, Any]) -> None:
        """Connect and log in, unless the cache holds a live session."""
        smbclient = _smbclient()
        try:
            smbclient.register_session(
                self.host, connection_timeout=int(max(1, self._connect_timeout)), **self._options(cache)
            )
        except Exception as exc:
            from smbprotocol.exceptions import (  # type: ignore[import-untyped]
                LogonFailure,
                SMBAuthenticationError,
            )

            refused = isinstance(exc, LogonFailure | SMBAuthenticationError)
            why = "wrong user name or password" if isinstance(exc, LogonFailure) else _why(exc)
            raise _LoginError(why, refused=refused) from exc

    async def _call(
        self, path: str, blocking: Callable[[dict[str, Any], str], _T], *, retry: bool = True
    ) -> _T:
        """Run ``blocking(cache, unc_path)`` in a thread; translate errors; reconnect once if lost."""
        from smbprotocol.exceptions import SMBOSError

        relative = normalise_relative(path)
        unc = self._unc(relative)
        for attempt in (1, 2):
            cache = self._cache

            def run(cache: dict[str, Any] = cache) -> _T:
                self._blocking_session(cache)
                return blocking(cache, unc)

            try:
                return await asyncio.wait_for(in_thread(run), self._timeout)
            except _LoginError as exc:
                self._abandon(cache)
                reason = (
                    f"SMB server {self.server} refused the login: {exc}"
                    if exc.refused
                    else f"cannot reach SMB server {self.server}: {exc}"
                )
                raise VfsError(reason, path=relative) from exc
            except SMBOSError as exc:
                raise _file_error(exc, relative, self.server) from exc
            except VfsError:
                raise
            except TimeoutError as exc:
                self._abandon(cache)
                raise VfsError(
                    f"SMB server {self.server} did not answer within {self._timeout:g} s", path=relative
                ) from exc
            except Exception as exc:  # the connection broke: smbprotocol raises several kinds
                self._abandon(cache)
                if attempt == 2 or not retry:
                    reason = f"lost the connection to SMB server {self.server}: {_why(exc)}"
                    raise VfsError(reason, path=relative) from exc
        raise AssertionError("unreachable")

    def _abandon(self, cache: dict[str, Any]) -> None:
        """Drop a connection that may hang: shut its sockets (ends waiting threads), start afresh."""
        if cache is self._cache:
            self._cache = {}
        for connection in list(cache.values()):
            with contextlib.suppress(Exception):
                connection.transport.close()
        cache.clear()

    # --- FileRoot ------------------------------------------------------------------------------

    async def read_bytes(self, path: str) -> bytes:
        return await self._call(path, self._blocking_read)

    def _blocking_read(self, cache: dict[str, Any], unc: str) -> bytes:
        smbclient = _smbclient()
        with _closing(smbclient.open_file(unc, mode="rb", **self._options(cache))) as file:
            data: bytes = file.read()
            return data

    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        if not normalise_relative(path):
            raise VfsError("is a directory")
        await self._call(path, partial(self._blocking_write, data=bytes(data)))

    def _blocking_write(self, cache: dict[str, Any], unc: str, *, data: bytes) -> None:
        smbclient = _smbclient()
        options = self._options(cache)
        directory = unc.rsplit("\\", 1)[0]
        temp = f"{directory}\\{TEMP_PREFIX}{secrets.token_hex(8)}"
        try:
            file = smbclient.open_file(temp, mode="wb", **options)
        except OSError as exc:
            if exc.errno != errno.ENOENT or not self.mkdir:
                raise
            smbclient.makedirs(directory, exist_ok=True, **options)
            file = smbclient.open_file(temp, mode="wb", **options)
        try:
            with _closing(file):
                file.write(data)
            smbclient.replace(temp, unc, **options)
        except BaseException:
            with contextlib.suppress(Exception):
                smbclient.remove(temp, **options)
            raise

    async def exists(self, path: str) -> bool:
        if not normalise_relative(path):
            return True  # the root appears with the first write
        return await self._call(path, self._blocking_exists)

    def _blocking_exists(self, cache: dict[str, Any], unc: str) -> bool:
        smbclient = _smbclient()
        try:
            smbclient.stat(unc, **self._options(cache))
        except OSError as exc:
            if exc.errno in (errno.ENOENT, errno.ENOTDIR):
                return False
            raise
        return True

    async def listdir(self, path: str) -> list[str]:
        missing_is_empty = not normalise_relative(path) and self.mkdir
        return await self._call(path, partial(self._blocking_listdir, missing_is_empty=missing_is_empty))

    def _blocking_listdir(self, cache: dict[str, Any], unc: str, *, missing_is_empty: bool) -> list[str]:
        smbclient = _smbclient()
        try:
            names = smbclient.listdir(unc, **self._options(cache))
        except OSError as exc:
            if missing_is_empty and exc.errno == errno.ENOENT:
                return []
            raise
        return sorted(name for name in names if not name.startswith(TEMP_PREFIX))

    async def remove(self, path: str) -> None:
        await self._call(path, self._blocking_remove, retry=False)

    def _blocking_remove(self, cache: dict[str, Any], unc: str) -> None:
        smbclient = _smbclient()
        smbclient.remove(unc, **self._options(cache))

    async def size(self, path: str) -> int:
        return await self._call(path, self._blocking_size)

    def _blocking_size(self, cache: dict[str, Any], unc: str) -> int:
        smbclient = _smbclient()
        info = smbclient.stat(unc, **self._options(cache))
        if stat.S_ISDIR(info.st_mode):
            raise VfsError("is a directory")
        return int(info.st_size)

    async def list_files(self, under: str = "") -> list[str]:
        try:
            start = normalise_relative(under)
        except VfsError:
            return []
        return await self._call(under, partial(self._blocking_list_files, start=start))

    def _blocking_list_files(self, cache: dict[str, Any], unc: str, *, start: str) -> list[str]:
        smbclient = _smbclient()
        found: list[str] = []
        pending = [(start, unc)]
        while pending:
            relative, directory = pending.pop()
            try:
                entries = list(smbclient.scandir(directory, **self._options(cache)))
            except OSError as exc:
                if exc.errno in (errno.ENOENT, errno.ENOTDIR):
                    continue  # missing, gone meanwhile, or not a directory
                raise
            for entry in entries:
                if entry.name.startswith(TEMP_PREFIX):
                    continue
                child = f"{relative}/{entry.name}" if relative else entry.name
                if entry.is_dir():
                    pending.append((child, f"{directory}\\{entry.name}"))
                else:
                    found.append(child)
        return sorted(found)

    async def checksum(self, path: str, algorithm: str = "sha256") -> str:
        new_hash(algorithm)  # an unknown algorithm fails here, before any I/O
        return await self._call(path, partial(self._blocking_checksum, algorithm=algorithm))

    def _blocking_checksum(self, cache: dict[str, Any], unc: str, *, algorithm: str) -> str:
        smbclient = _smbclient()
        digest = new_hash(algorithm)
        with _closing(smbclient.open_file(unc, mode="rb", **self._options(cache))) as file:
            while chunk := file.read(_CHUNK_BYTES):
                digest.update(chunk)
        return digest.hexdigest()

    async def close(self) -> None:
        cache, self._cache = self._cache, {}
        if not cache:
            return
        try:
            await asyncio.wait_for(in_thread(partial(self._blocking_disconnect, cache)), _CLOSE_TIMEOUT)
        except Exception:  # a dead server: just drop the sockets
            self._abandon(cache)

    def _blocking_disconnect(self, cache: dict[str, Any]) -> None:
        smbclient = _smbclient()
        smbclient.reset_connection_cache(fail_on_error=False, connection_cache=cache)


def _smbclient() -> Any:
    """smbclient, imported on first use (it is slow to import and most programs need no SMB)."""
    import smbclient  # type: ignore[import-untyped]

    return smbclient


@contextlib.contextmanager
def _closing(file: Any) -> Iterator[Any]:
    """Close an smbclient file; if the connection died, forget the handle (it died with it)."""
    try:
        yield file
    finally:
        try:
            file.close()
        except Exception:
            with contextlib.suppress(AttributeError):
                # smbprotocol has no public way to drop a handle whose connection is gone; without
                # this the file warns of an unclosed handle when it is collected.
                file.raw.fd._connected = False
            raise


def _file_error(exc: OSError, relative: str, server: str) -> VfsError:
    """Translate an smbclient OSError about a file into the VFS error tree."""
    if getattr(exc, "ntstatus", None) in _NO_SHARE:
        return VfsError(f"SMB server {server}: no such share", path=relative)
    if exc.errno in (errno.ENOENT, errno.ENOTDIR):
        return VfsFileNotFoundError("no such file or directory", path=relative)
    if exc.errno == errno.EISDIR:
        return VfsError("is a directory", path=relative)
    if exc.errno in (errno.EACCES, errno.EPERM):
        return VfsError(f"permission denied on SMB server {server}", path=relative)
    return VfsError(f"SMB server {server} refused: {exc.strerror or exc}", path=relative)


def _why(exc: BaseException) -> str:
    return str(exc) or type(exc).__name__
