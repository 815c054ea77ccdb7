"""VFS roots on the local disk, with atomic writes and symlinks kept inside the root."""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from abc import abstractmethod
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import TypeVar

from nightcrew.config import DataPath
from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs._errors import VfsError, VfsFileNotFoundError, VfsPathError
from nightcrew.vfs._paths import normalise_relative
from nightcrew.vfs._root import FileRoot, in_thread, new_hash

__all__ = ["TEMP_PREFIX", "DiskRoot", "LocalFile", "blocking_sync_directory"]

_T = TypeVar("_T")

#: Name prefix of the temporary files of atomic writes; hidden from listdir and find so that
#: nobody picks up a half-written file.
TEMP_PREFIX = ".nightcrew-tmp-"

_CHUNK_BYTES = 1 << 20


def _umask() -> int:
    """Return the process umask without changing it (Linux), else the usual 022."""
    try:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    return 0o022


def _os_error(exc: OSError, path: str) -> VfsError:
    """Translate an OSError at the boundary into the VFS error tree."""
    if isinstance(exc, FileNotFoundError | NotADirectoryError):
        return VfsFileNotFoundError("no such file or directory", path=path)
    if isinstance(exc, IsADirectoryError):
        return VfsError("is a directory", path=path)
    if isinstance(exc, PermissionError):
        return VfsError("permission denied", path=path)
    return VfsError(exc.strerror or str(exc), path=path)


def blocking_sync_directory(directory: Path) -> None:
    """Flush ``directory``'s entries to disk (a rename into it, a file removed from it)."""
    descriptor = os.open(directory, os.O_RDONLY | os.O_DIRECTORY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


class DiskRoot(FileRoot):
    """Files in a directory on the local disk; subclasses say which directory.

    Every path is resolved (symlinks followed) and must stay inside the resolved root, so a link
    to ``/etc`` inside the root is refused with :class:`VfsPathError`. Writes go to a temporary
    file in the target's directory, are flushed to disk (fsync) and then renamed over the target,
    and the directory is flushed too, so a crash leaves the old file or the new one, never half of
    one, and a write that returned survives a power cut.
    """

    #: Create the root and missing parent directories when writing.
    mkdir: bool = True

    @abstractmethod
    def _blocking_root_dir(self) -> Path:
        """Return the resolved root directory (may touch the disk: called in a worker thread)."""

    # --- paths ---------------------------------------------------------------------------------

    def _blocking_resolve(self, path: str) -> tuple[Path, Path]:
        """Return ``(unresolved, resolved)`` disk paths for ``path``, refusing escapes via symlinks."""
        root = self._blocking_root_dir()
        relative = normalise_relative(path)
        unresolved = root / relative if relative else root
        resolved = unresolved.resolve()
        if not resolved.is_relative_to(root):
            raise VfsPathError("a symlink leads out of the root", path=relative)
        return unresolved, resolved

    async def _in_thread(self, path: str, call: Callable[[], _T]) -> _T:
        """Run blocking ``call()`` about ``path`` in a worker thread, translating OSError."""
        try:
            return await in_thread(call)
        except OSError as exc:
            raise _os_error(exc, normalise_relative(path)) from exc

    # --- FileRoot ------------------------------------------------------------------------------

    async def read_bytes(self, path: str) -> bytes:
        return await self._in_thread(path, partial(self._blocking_read, path))

    def _blocking_read(self, path: str) -> bytes:
        return self._blocking_resolve(path)[1].read_bytes()

    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        await self._in_thread(path, partial(self._blocking_write, path, data))

    def _blocking_write(self, path: str, data: bytes | bytearray | memoryview) -> None:
        if not normalise_relative(path):
            raise IsADirectoryError(path)
        _, target = self._blocking_resolve(path)
        if self.mkdir:
            target.parent.mkdir(parents=True, exist_ok=True)
        try:
            mode = stat.S_IMODE(target.stat().st_mode)  # keep the mode of the file we replace
        except FileNotFoundError:
            mode = 0o666 & ~_umask()
        fd, temp_name = tempfile.mkstemp(prefix=TEMP_PREFIX, dir=target.parent)
        try:
            with os.fdopen(fd, "wb") as temp:
                os.fchmod(temp.fileno(), mode)
                temp.write(data)
                temp.flush()
                os.fsync(temp.fileno())  # content on disk before the rename makes it visible
            os.replace(temp_name, target)
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(temp_name)
            raise
        blocking_sync_directory(target.parent)  # the rename itself on disk: it outlives a power cut

    async def exists(self, path: str) -> bool:
        return await self._in_thread(path, partial(self._blocking_exists, path))

    def _blocking_exists(self, path: str) -> bool:
        _, resolved = self._blocking_resolve(path)
        # With mkdir the root appears with the first write; until then it exists, empty.
        return resolved.exists() or (self.mkdir and resolved == self._blocking_root_dir())

    async def listdir(self, path: str) -> list[str]:
        return await self._in_thread(path, partial(self._blocking_listdir, path))

    def _blocking_listdir(self, path: str) -> list[str]:
        _, directory = self._blocking_resolve(path)
        if self.mkdir and directory == self._blocking_root_dir() and not directory.exists():
            return []  # the root appears with the first write
        return sorted(name for name in os.listdir(directory) if not name.startswith(TEMP_PREFIX))

    async def remove(self, path: str) -> None:
        await self._in_thread(path, partial(self._blocking_remove, path))

    def _blocking_remove(self, path: str) -> None:
        unresolved, _ = self._blocking_resolve(path)
        # Remove the link itself, not what it points to (the check above kept that inside the root).
        if unresolved.is_dir() and not unresolved.is_symlink():
            raise IsADirectoryError(path)
        unresolved.unlink()

    async def size(self, path: str) -> int:
        return await self._in_thread(path, partial(self._blocking_size, path))

    def _blocking_size(self, path: str) -> int:
        _, resolved = self._blocking_resolve(path)
        info = resolved.stat()
        if stat.S_ISDIR(info.st_mode):
            raise IsADirectoryError(path)
        return info.st_size

    async def list_files(self, under: str = "") -> list[str]:
        return await self._in_thread(under, partial(self._blocking_list_files, under))

    def _blocking_list_files(self, under: str) -> list[str]:
        root = self._blocking_root_dir()
        try:
            _, start = self._blocking_resolve(under)
        except VfsPathError:
            return []
        found: list[str] = []
        # os.walk does not follow directory symlinks, so the walk stays inside the root.
        for directory, _, files in os.walk(start):
            for name in files:
                if name.startswith(TEMP_PREFIX):
                    continue
                full = Path(directory, name)
                if full.is_symlink() and not full.resolve().is_relative_to(root):
                    continue  # a link leading out of the root is not ours to offer
                found.append(full.relative_to(root).as_posix())
        return sorted(found)

    async def checksum(self, path: str, algorithm: str = "sha256") -> str:
        digest = new_hash(algorithm)  # fails early, outside the thread, on a bad name

        def blocking_checksum() -> str:
            with self._blocking_resolve(path)[1].open("rb") as file:
                while chunk := file.read(_CHUNK_BYTES):
                    digest.update(chunk)
            return digest.hexdigest()

        return await self._in_thread(path, blocking_checksum)


class LocalFile(DiskRoot):
    """Files in a directory on the local disk, e.g. ``/data/images``.

    Args:
        root: Directory holding the files; a relative one is taken relative to the working
            directory at first use.
        mkdir: Create the root and missing parent directories when writing. Without it, writing
            into a missing directory fails with :class:`VfsFileNotFoundError`.

    Symlinks inside the root may point anywhere inside it; one leading out is refused. Writes are
    atomic (see :class:`DiskRoot`).
    """

    def __init__(self, root: DataPath, *, mkdir: bool = True) -> None:
        if not isinstance(root, str) or not root:
            raise InvalidArgumentError("LocalFile root must be a non-empty directory path")
        self.root = root
        self.mkdir = mkdir
        self._resolved_root: Path | None = None

    def __repr__(self) -> str:
        return f"LocalFile({self.root!r})"

    def _blocking_root_dir(self) -> Path:
        if self._resolved_root is None:
            self._resolved_root = Path(self.root).resolve()
        return self._resolved_root
