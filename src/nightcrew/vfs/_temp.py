"""A VFS root in a private temporary directory that disappears on close."""

from __future__ import annotations

import shutil
import tempfile
import threading
from functools import partial
from pathlib import Path

from nightcrew.errors import InvalidArgumentError
from nightcrew.vfs._errors import VfsError
from nightcrew.vfs._local import DiskRoot
from nightcrew.vfs._root import in_thread

__all__ = ["TempFile"]


class TempFile(DiskRoot):
    """Files in a temporary directory, created at first use and removed with its content by
    :meth:`close`.

    Args:
        prefix: Start of the temporary directory's name (in the system temp directory).

    After :meth:`close`, every operation raises :class:`VfsError`.
    """

    def __init__(self, prefix: str = "nightcrew-") -> None:
        if "/" in prefix or "\x00" in prefix:
            raise InvalidArgumentError(f"TempFile prefix must be a plain name, got {prefix!r}")
        self.prefix = prefix
        self._directory: Path | None = None
        self._closed = False
        # Worker threads may ask for the directory at the same time: create it only once.
        self._directory_lock = threading.Lock()

    @property
    def directory(self) -> Path | None:
        """The real directory, or None before first use and after close (for tests and logs)."""
        return self._directory

    def __repr__(self) -> str:
        return f"TempFile(prefix={self.prefix!r})"

    def _blocking_root_dir(self) -> Path:
        with self._directory_lock:
            if self._closed:
                raise VfsError("TempFile is closed")
            if self._directory is None:
                self._directory = Path(tempfile.mkdtemp(prefix=self.prefix)).resolve()
            return self._directory

    async def close(self) -> None:
        with self._directory_lock:
            directory, self._directory = self._directory, None
            self._closed = True
        if directory is not None:
            await in_thread(partial(self._blocking_remove_tree, directory))

    @staticmethod
    def _blocking_remove_tree(directory: Path) -> None:
        shutil.rmtree(directory, ignore_errors=True)
