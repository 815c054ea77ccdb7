"""A VFS root on an SSH server, over SFTP (asyncssh).

Chosen: asyncssh, a well-kept pure-asyncio SSH library with a complete SFTP client (the
``posix-rename`` and ``fsync`` extensions of OpenSSH included), so nothing blocks the event loop.

* **Keys and host keys.** The login is by key (``client_keys``, or the user's default keys and
  agent). The server's host key must be in ``known_hosts`` (``~/.ssh/known_hosts`` by default);
  an unknown or changed key refuses the connection. There is no option to skip the check.
* **Reconnect.** One SSH connection is opened on first use and kept. When it is lost (server
  restarted, link cut, keepalives unanswered) the operation that noticed it is tried once more on
  a fresh connection — all operations are idempotent except :meth:`SSHFile.remove`, which is not
  retried — and if that fails too it raises :class:`VfsError` naming the server; the next call
  connects again. Every operation is bounded by ``timeout``.
* **Atomic writes.** Data goes to a hidden temporary file (``.nightcrew-tmp-…``) beside the target,
  is flushed (``fsync@openssh.com`` when offered) and renamed over the target with
  ``posix-rename@openssh.com``: a reader, or a copy cut off by a dead server, leaves the old file
  or the new one, never half of one. A server without that extension gets remove-then-rename,
  which is not atomic. A temporary file orphaned by a lost connection is hidden from
  ``listdir``/``find`` and may be deleted by hand.
* Symbolic links on the server are followed as the server follows them: the account's
  permissions, not this root, limit what it reaches.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import posixpath
import secrets
import stat
from collections.abc import Awaitable, Callable
from typing import TYPE_CHECKING, TypeVar, cast

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs._errors import VfsError, VfsFileNotFoundError
from nightcrew.vfs._local import TEMP_PREFIX
from nightcrew.vfs._paths import normalise_relative
from nightcrew.vfs._root import FileRoot, new_hash

if TYPE_CHECKING:
    import asyncssh

__all__ = ["SSHFile"]

_T = TypeVar("_T")
_CHUNK_BYTES = 1 << 20


class SSHFile(FileRoot):
    """Files in a directory on an SSH server.

    Args:
        host: The server's name or address.
        root: Directory on the server holding the files (relative: to the login's home).
        username: Login name; the local user's by default.
        port: The server's port.
        client_keys: Private key files to log in with; the user's default keys and agent if None.
        known_hosts: known_hosts file listing the server's host key; ``~/.ssh/known_hosts`` if None.
        connect_timeout: Wall seconds a connection (with login) may take.
        timeout: Wall seconds one operation may take.
        keepalive: Wall seconds between keepalives on an idle connection (3 unanswered: lost).
        mkdir: Create missing directories when writing.
    """

    def __init__(
        self,
        host: str,
        *,
        root: str,
        username: str | None = None,
        port: int = 22,
        client_keys: list[str] | None = None,
        known_hosts: str | None = None,
        connect_timeout: float = 15.0,
        timeout: float = 60.0,
        keepalive: float = 15.0,
        mkdir: bool = True,
    ) -> None:
        if not isinstance(host, str) or not host:
            raise InvalidArgumentError("SSHFile host must be a non-empty name or address")
        if not isinstance(root, str) or not root:
            raise InvalidArgumentError("SSHFile root must be a non-empty directory path")
        if not isinstance(port, int) or not 0 < port < 65536:
            raise InvalidArgumentError(f"SSHFile port must be 1..65535, got {port!r}")
        for name, value in (
            ("connect_timeout", connect_timeout),
            ("timeout", timeout),
            ("keepalive", keepalive),
        ):
            if not value > 0:
                raise InvalidArgumentError(f"SSHFile {name} must be > 0 seconds, got {value}")
        if client_keys is not None and not (isinstance(client_keys, list) and client_keys):
            raise InvalidArgumentError("SSHFile client_keys must be a list of key files, or left out")
        self.host, self.port, self.root = host, port, root.rstrip("/") or "/"
        self.username = username
        self._client_keys = client_keys
        self._known_hosts = os.path.expanduser(known_hosts or "~/.ssh/known_hosts")
        self._connect_timeout, self._timeout = float(connect_timeout), float(timeout)
        self._keepalive = float(keepalive)
        self.mkdir = mkdir
        self._connection: asyncssh.SSHClientConnection | None = None
        self._sftp: asyncssh.SFTPClient | None = None
        self._connecting: asyncio.Lock | None = None  # made in the running loop

    @property
    def server(self) -> str:
        """``user@host:port`` (or ``host:port``), as errors name the server."""
        return f"{self.username + '@' if self.username else ''}{self.host}:{self.port}"

    def __repr__(self) -> str:
        return f"SSHFile({self.server!r}, root={self.root!r})"

    # --- the connection ------------------------------------------------------------------------

    async def _client(self, relative: str) -> asyncssh.SFTPClient:
        """The SFTP client, connecting (again) when there is none or its connection is gone."""
        if self._connecting is None:
            self._connecting = asyncio.Lock()
        async with self._connecting:
            if self._sftp is not None and self._connection is not None and not self._connection.is_closed():
                return self._sftp
            await self._drop()
            self._connection, self._sftp = await self._connect(relative)
            return self._sftp

    async def _connect(self, relative: str) -> tuple[asyncssh.SSHClientConnection, asyncssh.SFTPClient]:
        import asyncssh

        if not os.access(self._known_hosts, os.R_OK):
            raise VfsError(
                f"cannot read known_hosts file {self._known_hosts} (needed to check {self.host}'s host key)",
                path=relative,
            )
        try:
            async with asyncio.timeout(self._connect_timeout):
                connection = await asyncssh.connect(
                    self.host,
                    self.port,
                    username=self.username or (),
                    client_keys=self._client_keys or (),
                    known_hosts=self._known_hosts,
                    config=None,  # the settings are these arguments, not ~/.ssh/config
                    keepalive_interval=self._keepalive,
                    keepalive_count_max=3,
                )
                try:
                    sftp = await connection.start_sftp_client()
                except BaseException:
                    connection.abort()
                    raise
        except asyncssh.HostKeyNotVerifiable as exc:
            raise VfsError(
                f"host key of SSH server {self.server} not trusted ({exc.reason}); "
                f"add it to {self._known_hosts}",
                path=relative,
            ) from exc
        except asyncssh.PermissionDenied as exc:
            raise VfsError(
                f"SSH server {self.server} refused the login: {exc.reason}", path=relative
            ) from exc
        except TimeoutError as exc:
            raise VfsError(
                f"cannot reach SSH server {self.server}: no answer within {self._connect_timeout:g} s",
                path=relative,
            ) from exc
        except (OSError, asyncssh.Error) as exc:
            raise VfsError(f"cannot reach SSH server {self.server}: {_why(exc)}", path=relative) from exc
        return connection, sftp

    async def _drop(self) -> None:
        """Forget the connection (aborted, not closed: it may hang on a dead link)."""
        connection, self._connection, self._sftp = self._connection, None, None
        if connection is not None:
            connection.abort()

    async def _call(
        self, path: str, operation: Callable[[asyncssh.SFTPClient, str], Awaitable[_T]], *, retry: bool = True
    ) -> _T:
        """Run ``operation(sftp, remote_path)``; translate errors; reconnect once if the link is lost."""
        import asyncssh

        relative = normalise_relative(path)
        remote = posixpath.join(self.root, relative) if relative else self.root
        for attempt in (1, 2):
            sftp = await self._client(relative)
            try:
                async with asyncio.timeout(self._timeout):
                    return await operation(sftp, remote)
            except TimeoutError as exc:  # before OSError, its base: a silent server is not retried
                await self._drop()
                raise VfsError(
                    f"SSH server {self.server} did not answer within {self._timeout:g} s", path=relative
                ) from exc
            except (OSError, asyncssh.Error) as exc:
                if isinstance(exc, asyncssh.SFTPError) and not isinstance(
                    exc, asyncssh.SFTPConnectionLost | asyncssh.SFTPNoConnection
                ):
                    raise await _explain(sftp, exc, remote, relative, self.server) from exc
                await self._drop()
                if attempt == 2 or not retry:
                    raise VfsError(
                        f"lost the connection to SSH server {self.server}: {_why(exc)}", path=relative
                    ) from exc
        raise AssertionError("unreachable")

    # --- FileRoot ------------------------------------------------------------------------------

    async def read_bytes(self, path: str) -> bytes:
        async def read(sftp: asyncssh.SFTPClient, remote: str) -> bytes:
            async with sftp.open(remote, "rb") as file:
                data: bytes = await file.read()
                return data

        return await self._call(path, read)

    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        if not normalise_relative(path):
            raise VfsError("is a directory")
        payload = bytes(data)
        await self._call(path, lambda sftp, remote: self._write(sftp, remote, payload))

    async def _write(self, sftp: asyncssh.SFTPClient, remote: str, data: bytes) -> None:
        import asyncssh

        directory = posixpath.dirname(remote)
        temp = posixpath.join(directory, f"{TEMP_PREFIX}{secrets.token_hex(8)}")
        try:
            mode: int | None = stat.S_IMODE((await sftp.stat(remote)).permissions or 0) or None
        except asyncssh.SFTPNoSuchFile:
            mode = None  # a new file: the server's umask decides
        try:
            file = await sftp.open(temp, "wb", asyncssh.SFTPAttrs(permissions=mode))
        except asyncssh.SFTPNoSuchFile:
            if not self.mkdir:
                raise
            await sftp.makedirs(directory, exist_ok=True)
            file = await sftp.open(temp, "wb", asyncssh.SFTPAttrs(permissions=mode))
        try:
            async with file:
                await file.write(data)
                with contextlib.suppress(asyncssh.SFTPOpUnsupported):
                    await file.fsync()  # on the server's disk before the rename shows it
            try:
                await sftp.posix_rename(temp, remote)
            except asyncssh.SFTPOpUnsupported:
                with contextlib.suppress(asyncssh.SFTPNoSuchFile):
                    await sftp.remove(remote)
                await sftp.rename(temp, remote)
        except BaseException:
            with contextlib.suppress(Exception):
                await asyncio.shield(sftp.remove(temp))
            raise

    async def exists(self, path: str) -> bool:
        import asyncssh

        if not normalise_relative(path):
            return True  # the root appears with the first write

        async def exists(sftp: asyncssh.SFTPClient, remote: str) -> bool:
            try:
                await sftp.stat(remote)
            except asyncssh.SFTPNoSuchFile:
                return False
            return True

        return await self._call(path, exists)

    async def listdir(self, path: str) -> list[str]:
        import asyncssh

        async def listdir(sftp: asyncssh.SFTPClient, remote: str) -> list[str]:
            try:
                names = await sftp.listdir(remote)
            except asyncssh.SFTPNoSuchFile:
                if remote == self.root and self.mkdir:
                    return []
                raise
            return sorted(n for n in names if n not in (".", "..") and not n.startswith(TEMP_PREFIX))

        return await self._call(path, listdir)

    async def remove(self, path: str) -> None:
        await self._call(path, lambda sftp, remote: sftp.remove(remote), retry=False)

    async def size(self, path: str) -> int:
        async def size(sftp: asyncssh.SFTPClient, remote: str) -> int:
            attrs = await sftp.stat(remote)
            if stat.S_ISDIR(attrs.permissions or 0):
                raise VfsError("is a directory")
            return int(attrs.size or 0)

        return await self._call(path, size)

    async def list_files(self, under: str = "") -> list[str]:
        import asyncssh

        try:
            start = normalise_relative(under)
        except VfsError:
            return []

        async def walk(sftp: asyncssh.SFTPClient, remote: str) -> list[str]:
            found: list[str] = []
            pending = [start]
            while pending:
                relative = pending.pop()
                directory = posixpath.join(self.root, relative) if relative else self.root
                try:
                    entries = await sftp.readdir(directory)
                except (asyncssh.SFTPNoSuchFile, asyncssh.SFTPFailure):
                    continue  # gone meanwhile, or not a directory
                for entry in entries:
                    name = str(entry.filename)
                    if name in (".", "..") or name.startswith(TEMP_PREFIX):
                        continue
                    child = f"{relative}/{name}" if relative else name
                    if stat.S_ISDIR(entry.attrs.permissions or 0):
                        pending.append(child)
                    else:
                        found.append(child)
            return sorted(found)

        return await self._call(under, walk)

    async def checksum(self, path: str, algorithm: str = "sha256") -> str:
        new_hash(algorithm)  # an unknown algorithm fails here, before any I/O

        async def checksum(sftp: asyncssh.SFTPClient, remote: str) -> str:
            digest = new_hash(algorithm)  # fresh for each attempt
            async with sftp.open(remote, "rb") as file:
                while chunk := cast(bytes, await file.read(_CHUNK_BYTES)):
                    digest.update(chunk)
            return digest.hexdigest()

        return await self._call(path, checksum)

    async def close(self) -> None:
        await self._drop()


async def _explain(
    sftp: asyncssh.SFTPClient, exc: asyncssh.SFTPError, remote: str, relative: str, server: str
) -> VfsError:
    """The VFS error for an SFTP status; a bare "failure" is explained by a look at the path."""
    import asyncssh

    if isinstance(exc, asyncssh.SFTPNoSuchFile | asyncssh.SFTPNoSuchPath):
        return VfsFileNotFoundError("no such file or directory", path=relative)
    if isinstance(exc, asyncssh.SFTPPermissionDenied):
        return VfsError(f"permission denied on SSH server {server}", path=relative)
    if isinstance(exc, asyncssh.SFTPFileIsADirectory):
        return VfsError("is a directory", path=relative)
    with contextlib.suppress(asyncssh.Error, OSError):
        if stat.S_ISDIR((await sftp.stat(remote)).permissions or 0):
            return VfsError("is a directory", path=relative)
    return VfsError(f"SSH server {server} refused: {exc.reason}", path=relative)


def _why(exc: BaseException) -> str:
    reason = getattr(exc, "reason", None)
    return str(reason or exc) or type(exc).__name__
