"""Frames on disk: ``<storage>/<DAY-OBS>/<INSTRUME>/<basename>``, written atomically.

A frame is written to a hidden temporary file in its final directory, flushed to disk (fsync),
then renamed over its final name and the directory flushed, so a file under its final name is
always complete. The index row is committed only after that; when the commit fails the file is
removed again (:meth:`FrameStore.discard`). Blocking: run in a thread.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
from pathlib import Path

__all__ = ["FrameStore", "storage_path"]

_UNSAFE = re.compile(r"[^A-Za-z0-9._-]")
TEMP_PREFIX = ".upload-"


def storage_path(day_obs: str, instrument: str, basename: str) -> str:
    """The frame's path relative to the storage directory."""
    folder = _UNSAFE.sub("_", instrument).strip(".") or "unknown"
    return f"{day_obs}/{folder}/{basename}"


class FrameStore:
    """The directory holding the frames."""

    def __init__(self, root: Path) -> None:
        self.root = root

    def absolute(self, relative: str) -> Path:
        return self.root / relative

    def blocking_write(self, relative: str, data: bytes) -> None:
        """Put ``data`` at ``relative``, complete or not at all; refuses to replace a file."""
        target = self.absolute(relative)
        target.parent.mkdir(parents=True, exist_ok=True)
        temporary = target.parent / f"{TEMP_PREFIX}{secrets.token_hex(8)}"
        try:
            with open(temporary, "xb") as out:
                out.write(data)
                out.flush()
                os.fsync(out.fileno())
            if target.exists():
                raise FileExistsError(f"{relative} is already on disk")
            os.replace(temporary, target)
        finally:
            with contextlib.suppress(FileNotFoundError):
                temporary.unlink()
        _sync_directory(target.parent)

    def blocking_remove_temporaries(self) -> list[Path]:
        """Remove the temporary files of uploads cut off by a crash; return them."""
        left = sorted(self.root.glob(f"*/*/{TEMP_PREFIX}*"))
        for path in left:
            with contextlib.suppress(FileNotFoundError):
                path.unlink()
        return left

    def blocking_discard(self, relative: str) -> None:
        """Remove a file whose index row could not be committed."""
        target = self.absolute(relative)
        with contextlib.suppress(FileNotFoundError):
            target.unlink()
        _sync_directory(target.parent)


def _sync_directory(directory: Path) -> None:
    descriptor = os.open(directory, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)
