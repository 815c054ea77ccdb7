"""The small interface every VFS root implements.

A root stores files under relative paths (``a/b.fits``; ``""`` is the root itself). The
:class:`~nightcrew.vfs.VirtualFileSystem` checks and normalises paths before calling a root, and a
root normalises them again with :func:`normalise_relative`, so a root used on its own is just as
safe. Writes must be atomic: a reader sees the old content or the new one, never a mixture.
"""

from __future__ import annotations

import asyncio
import hashlib
from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import TypeVar

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs._paths import glob_regex, normalise_relative, static_prefix

__all__ = ["FileRoot", "in_thread", "new_hash"]

_T = TypeVar("_T")


def new_hash(algorithm: str) -> hashlib._Hash:
    """Return a fresh hashlib object, or raise InvalidArgumentError naming the known algorithms."""
    try:
        return hashlib.new(algorithm)
    except ValueError as exc:
        known = ", ".join(sorted(hashlib.algorithms_guaranteed))
        raise InvalidArgumentError(f"unknown checksum algorithm {algorithm!r}; known: {known}") from exc


async def in_thread(call: Callable[[], _T]) -> _T:
    """Run blocking ``call()`` in the loop's default executor, *without* the caller's context.

    The roots' one way to block. Not :func:`asyncio.to_thread`: that copies the context variables,
    so every record a library logs in the thread would count as the calling module's and be sent
    as its LogEvent - and smbprotocol logs each file it opens or closes at INFO.
    """
    return await asyncio.get_running_loop().run_in_executor(None, call)


class FileRoot(ABC):
    """Storage behind one VFS root (``/cache``, ``/archive`` ...).

    Subclasses implement the abstract methods; :meth:`find` and :meth:`checksum` have generic
    implementations built on them. Constructors must not do I/O: acquire lazily, release in
    :meth:`close`.
    """

    @abstractmethod
    async def read_bytes(self, path: str) -> bytes:
        """Return the whole content of the file at ``path``."""

    @abstractmethod
    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        """Replace the file at ``path`` by ``data`` atomically, creating it if needed."""

    @abstractmethod
    async def exists(self, path: str) -> bool:
        """Return whether a file or directory exists at ``path`` (``""``, the root, always does)."""

    @abstractmethod
    async def listdir(self, path: str) -> list[str]:
        """Return the sorted names (not paths) of the entries of the directory at ``path``."""

    @abstractmethod
    async def remove(self, path: str) -> None:
        """Remove the file at ``path``; directories are not removed."""

    @abstractmethod
    async def size(self, path: str) -> int:
        """Return the size of the file at ``path`` in bytes."""

    @abstractmethod
    async def list_files(self, under: str = "") -> list[str]:
        """Return the sorted relative paths of all files below directory ``under``, at any depth.

        A missing ``under`` gives an empty list: :meth:`find` on a pattern whose directory does
        not exist finds nothing rather than failing.
        """

    async def find(self, pattern: str) -> list[str]:
        """Return the sorted relative paths of files matching a glob ``pattern``.

        ``*`` and ``?`` match within a path component, ``[abc]`` one character of a set, and a
        ``**`` component any number of directories: ``**/*.fits`` finds FITS files at any depth.
        """
        pattern = normalise_relative(pattern)
        regex = glob_regex(pattern)
        return [path for path in await self.list_files(static_prefix(pattern)) if regex.fullmatch(path)]

    async def checksum(self, path: str, algorithm: str = "sha256") -> str:
        """Return the hex digest of the file's content (any :mod:`hashlib` algorithm).

        Used to verify copies between roots. This generic version reads the whole file into
        memory; roots on disk override it to stream.
        """
        digest = new_hash(algorithm)
        digest.update(await self.read_bytes(path))
        return digest.hexdigest()

    async def close(self) -> None:
        """Release what the root holds (temp directories, connections); safe to call twice."""
        return  # most roots hold nothing
