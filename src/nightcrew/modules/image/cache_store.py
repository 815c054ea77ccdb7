"""The storage behind the HTTP file cache: files on disk, at most ``max_size`` bytes in all.

Layout of ``directory``: the files under ``files/`` (by their relative paths), and
``fetched.json``, the paths whose bytes a consumer has downloaded. A write is atomic and durable
before it returns (temporary file, fsync, rename, fsync of the directory: see
:class:`~nightcrew.vfs.LocalFile`), so the upload is acknowledged only once the frame would survive
``kill -9`` of the cache or a power cut. On :meth:`CacheStore.load` the store serves what is on disk
and removes the temporary files of writes a crash interrupted.

Eviction never drops a file nobody has fetched yet: when a write would push the total over
``max_size``, fetched files go first, oldest written first; if that cannot make room the write
is refused (:class:`CacheFullError`) and the camera's exposure fails loudly instead of a frame
vanishing. With ``max_age``, fetched files older than that many (wall) seconds are dropped too.
"""

from __future__ import annotations

import asyncio
import json
import logging
import os
import time
from collections import OrderedDict
from pathlib import Path

from nightcrew.vfs import LocalFile, VfsError
from nightcrew.vfs._local import TEMP_PREFIX
from nightcrew.vfs._paths import normalise_relative

__all__ = ["CacheFullError", "CacheStore", "TooLargeError"]

log = logging.getLogger(__name__)

_FETCHED_FILE = "fetched.json"


class TooLargeError(VfsError):
    """A single file is larger than the whole cache."""


class CacheFullError(VfsError):
    """No room without evicting files that no consumer has fetched yet."""


class CacheStore:
    """Files by relative path on disk, evicting fetched ones (oldest first) to stay in ``max_size``.

    Args:
        directory: Where the cache keeps its files (made on :meth:`load`).
        max_size: Bytes the files may take in all, > 0.
        max_age: Wall seconds a fetched file is kept at most; None: until room is needed.
    """

    def __init__(self, directory: str, max_size: int, *, max_age: float | None = None) -> None:
        if not max_size > 0:
            raise ValueError(f"max_size must be > 0 bytes, got {max_size}")
        if max_age is not None and not max_age > 0:
            raise ValueError(f"max_age must be > 0 seconds, got {max_age}")
        self.directory = Path(directory)
        self.max_size, self.max_age = max_size, max_age
        self.root = LocalFile(str(self.directory / "files"))  # reads and metadata go straight to it
        self._state = LocalFile(str(self.directory))
        self._written: OrderedDict[str, tuple[int, float]] = (
            OrderedDict()
        )  # path: size, wall time; oldest first
        self._fetched: set[str] = set()
        self._lock = asyncio.Lock()  # one change of the index at a time
        self.total = 0
        self.evicted = 0

    @property
    def unfetched(self) -> int:
        """How many files no consumer has fetched yet."""
        return len(self._written.keys() - self._fetched)

    async def load(self) -> None:
        """Index the files on disk (oldest first) and which were fetched; drop interrupted writes."""
        found = await asyncio.to_thread(_blocking_scan, self.directory / "files")
        self._written = OrderedDict(found)
        self.total = sum(size for size, _ in self._written.values())
        try:
            fetched = json.loads(await self._state.read_bytes(_FETCHED_FILE))
            self._fetched = {str(path) for path in fetched} & self._written.keys()
        except VfsError:
            self._fetched = set()  # none yet; a frame counted as not fetched is only kept longer
        except (ValueError, TypeError) as exc:
            log.warning("file cache: ignoring unreadable %s (%s); keeping every file", _FETCHED_FILE, exc)
            self._fetched = set()
        if self._written:
            log.info(
                "file cache: serving %d files (%d bytes) from %s, %d not fetched yet",
                len(self._written), self.total, self.directory, self.unfetched,
            )  # fmt: skip

    async def write(self, path: str, data: bytes) -> list[str]:
        """Store ``data`` at ``path`` durably; return the paths evicted to make room."""
        key = normalise_relative(path)
        if len(data) > self.max_size:
            raise TooLargeError(f"{len(data)} bytes exceed the cache size of {self.max_size}", path=key)
        async with self._lock:
            evicted = await self._make_room(key, len(data))
            await self.root.write_bytes(key, data)  # durable: LocalFile flushes file and directory
            self.total += len(data) - self._written.pop(key, (0, 0.0))[0]
            self._written[key] = (len(data), time.time())
            if key in self._fetched:  # rewritten: a new file nobody has fetched
                self._fetched.discard(key)
                await self._save_fetched()
            return evicted

    async def read(self, path: str) -> bytes:
        """The bytes at ``path`` (a download; call :meth:`mark_fetched` once it was delivered)."""
        return await self.root.read_bytes(path)

    async def mark_fetched(self, path: str) -> None:
        """``path`` reached a consumer: it may now be evicted."""
        key = normalise_relative(path)
        async with self._lock:
            if key in self._written and key not in self._fetched:
                self._fetched.add(key)
                await self._save_fetched()

    async def remove(self, path: str) -> None:
        key = normalise_relative(path)
        async with self._lock:
            await self._drop(key)
            await self._save_fetched()

    async def _make_room(self, key: str, size: int) -> list[str]:
        """Evict what must go before ``size`` bytes are written at ``key``; refuse if it cannot."""
        total = self.total - self._written.get(key, (0, 0.0))[0] + size
        now = time.time()
        victims = []
        for path, (old_size, written) in self._written.items():
            if path == key or path not in self._fetched:
                continue
            if total > self.max_size or (self.max_age is not None and now - written > self.max_age):
                victims.append(path)
                total -= old_size
        if total > self.max_size:
            raise CacheFullError(
                f"the file cache is full: {self.unfetched} files ({self.total} bytes in all) "
                f"wait for a consumer to fetch them",
                path=key,
            )
        for path in victims:
            await self._drop(path)
        if victims:
            await self._save_fetched()
            self.evicted += len(victims)
        return victims

    async def _drop(self, key: str) -> None:
        await self.root.remove(key)
        self.total -= self._written.pop(key, (0, 0.0))[0]
        self._fetched.discard(key)

    async def _save_fetched(self) -> None:
        await self._state.write_bytes(_FETCHED_FILE, json.dumps(sorted(self._fetched)).encode())


def _blocking_scan(files: Path) -> list[tuple[str, tuple[int, float]]]:
    """The files under ``files`` as (relative path, (size, mtime)), oldest first; removes the
    temporary files of interrupted writes."""
    found = []
    for directory, _, names in os.walk(files):
        for name in names:
            full = Path(directory, name)
            if name.startswith(TEMP_PREFIX):
                full.unlink(missing_ok=True)  # a write that a crash cut short: never acknowledged
                continue
            info = full.stat()
            found.append((full.relative_to(files).as_posix(), (info.st_size, info.st_mtime)))
    return sorted(found, key=lambda item: (item[1][1], item[0]))
