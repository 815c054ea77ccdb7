"""The storage behind the HTTP file cache: files in memory, at most ``max_size`` bytes in all.

When a write pushes the total over the limit, the files written longest ago are evicted first
(rewriting a file makes it new again). Path rules and errors are those of a MemoryFile root.
"""

from __future__ import annotations

from collections import OrderedDict

from nightcrew.vfs import MemoryFile, VfsError
from nightcrew.vfs._paths import normalise_relative

__all__ = ["BoundedStore", "TooLargeError"]


class TooLargeError(VfsError):
    """A single file is larger than the whole cache."""


class BoundedStore:
    """Files by relative path, evicting the oldest to stay within ``max_size`` bytes."""

    def __init__(self, max_size: int) -> None:
        if not max_size > 0:
            raise ValueError(f"max_size must be > 0 bytes, got {max_size}")
        self.max_size = max_size
        self.root = MemoryFile()  # private: reads go straight to it
        self._sizes: OrderedDict[str, int] = OrderedDict()  # oldest first
        self.total = 0
        self.evicted = 0

    async def write(self, path: str, data: bytes) -> list[str]:
        """Store ``data`` at ``path``; return the paths evicted to make room."""
        key = normalise_relative(path)
        if len(data) > self.max_size:
            raise TooLargeError(f"{len(data)} bytes exceed the cache size of {self.max_size}", path=key)
        await self.root.write_bytes(key, data)
        self.total += len(data) - self._sizes.pop(key, 0)
        self._sizes[key] = len(data)
        evicted = []
        while self.total > self.max_size:
            oldest = next(iter(self._sizes))
            await self.remove(oldest)
            evicted.append(oldest)
        self.evicted += len(evicted)
        return evicted

    async def remove(self, path: str) -> None:
        key = normalise_relative(path)
        await self.root.remove(key)
        self.total -= self._sizes.pop(key, 0)
