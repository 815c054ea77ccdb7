"""A VFS root that keeps files in memory, optionally shared by name within the process."""

from __future__ import annotations

from typing import ClassVar

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs._errors import VfsError, VfsFileNotFoundError
from nightcrew.vfs._paths import normalise_relative
from nightcrew.vfs._root import FileRoot

__all__ = ["MemoryFile"]


class MemoryFile(FileRoot):
    """Files held in a dict in this process; directories exist implicitly through their files.

    Args:
        name: With a name, the store is shared by every ``MemoryFile`` of that name in this
            process, so two modules running in one process (tests, simulations) exchange files by
            path as they would through a shared disk. Without a name, the store is private to this
            instance and emptied by :meth:`close`.

    Writes are atomic because the store is only changed between awaits; stored values are
    immutable ``bytes``.
    """

    _shared_stores: ClassVar[dict[str, dict[str, bytes]]] = {}

    def __init__(self, name: str | None = None) -> None:
        if name is not None and not name:
            raise InvalidArgumentError("MemoryFile name must not be empty (use None for a private store)")
        self.name = name
        self._private_store: dict[str, bytes] = {}

    @classmethod
    def clear_shared(cls, name: str | None = None) -> None:
        """Forget the shared store called ``name``, or all shared stores (for test isolation)."""
        if name is None:
            cls._shared_stores.clear()
        else:
            cls._shared_stores.pop(name, None)

    @property
    def _store(self) -> dict[str, bytes]:
        # Looked up on use, not in __init__, so a clear_shared() between tests takes effect.
        if self.name is None:
            return self._private_store
        return self._shared_stores.setdefault(self.name, {})

    def _file_key(self, path: str) -> str:
        """Normalise ``path`` and check that a file (not a directory) is stored there."""
        key = normalise_relative(path)
        if key not in self._store:
            if self._is_dir(key):
                raise VfsError("is a directory", path=key)
            raise VfsFileNotFoundError("no such file", path=key)
        return key

    def _is_dir(self, key: str) -> bool:
        prefix = key + "/" if key else ""
        return any(stored.startswith(prefix) for stored in self._store)

    async def read_bytes(self, path: str) -> bytes:
        return self._store[self._file_key(path)]

    async def write_bytes(self, path: str, data: bytes | bytearray | memoryview) -> None:
        key = normalise_relative(path)
        if not key:
            raise VfsError("is a directory", path="/")
        if self._is_dir(key):
            raise VfsError("is a directory", path=key)
        # A file cannot also be a directory: refuse "a/b" when "a" is a file, as a disk would.
        parts = key.split("/")
        for depth in range(1, len(parts)):
            parent = "/".join(parts[:depth])
            if parent in self._store:
                raise VfsError(f"'{parent}' is a file, not a directory", path=key)
        self._store[key] = bytes(data)

    async def exists(self, path: str) -> bool:
        key = normalise_relative(path)
        return not key or key in self._store or self._is_dir(key)

    async def listdir(self, path: str) -> list[str]:
        key = normalise_relative(path)
        if key in self._store:
            raise VfsError("not a directory", path=key)
        prefix = key + "/" if key else ""
        names = {
            stored[len(prefix) :].split("/", 1)[0] for stored in self._store if stored.startswith(prefix)
        }
        if key and not names:
            raise VfsFileNotFoundError("no such directory", path=key)
        return sorted(names)

    async def remove(self, path: str) -> None:
        del self._store[self._file_key(path)]

    async def size(self, path: str) -> int:
        return len(self._store[self._file_key(path)])

    async def list_files(self, under: str = "") -> list[str]:
        key = normalise_relative(under)
        prefix = key + "/" if key else ""
        return sorted(stored for stored in self._store if stored.startswith(prefix))

    async def close(self) -> None:
        """Empty a private store; a shared store stays for the other instances using it."""
        self._private_store.clear()

    def __repr__(self) -> str:
        return f"MemoryFile(name={self.name!r})" if self.name is not None else "MemoryFile()"
