"""What the ImageWatcher remembers between sweeps and restarts, and its retry backoff. Pure.

For every file it is moving it keeps the size and checksum it saw and the destinations that hold
a verified copy. Saved as JSON after every sweep, so a restart neither copies a file again to a
destination that already has it nor forgets one; losing the state costs only repeated copies,
never a file, because the original is deleted only after every copy was verified.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Backoff", "PendingFile", "WatchState"]


@dataclass
class PendingFile:
    """A file on its way: its size and checksum when first read, where a verified copy is, and
    which destinations refused its content for good (destination → their reason)."""

    size: int
    checksum: str | None = None
    verified: set[str] = field(default_factory=set)
    refused: dict[str, str] = field(default_factory=dict)


@dataclass
class WatchState:
    """Files being moved, by path relative to the watched directory."""

    files: dict[str, PendingFile] = field(default_factory=dict)

    def to_json(self) -> bytes:
        files = {
            name: {
                "size": f.size,
                "checksum": f.checksum,
                "verified": sorted(f.verified),
                "refused": dict(sorted(f.refused.items())),
            }
            for name, f in sorted(self.files.items())
        }
        return json.dumps({"version": 1, "files": files}, indent=1).encode()

    @classmethod
    def from_json(cls, data: bytes) -> WatchState:
        """The state saved by :meth:`to_json`; raises ValueError if it is not one."""
        loaded: Any = json.loads(data)
        if not isinstance(loaded, dict) or loaded.get("version") != 1:
            raise ValueError("not an image watcher state (version 1)")
        return cls(
            {
                name: PendingFile(
                    int(f["size"]),
                    f.get("checksum"),
                    set(f.get("verified", [])),
                    {str(d): str(why) for d, why in f.get("refused", {}).items()},
                )
                for name, f in loaded.get("files", {}).items()
            }
        )


class Backoff:
    """Waiting times after failures: ``first``, doubling up to ``maximum``; a success resets them."""

    def __init__(self, first: float, maximum: float) -> None:
        if not 0 < first <= maximum:
            raise ValueError(f"need 0 < first <= maximum, got {first} and {maximum}")
        self.first, self.maximum = first, maximum
        self.failures = 0
        self.retry_at = float("-inf")

    def ready(self, now: float) -> bool:
        return now >= self.retry_at

    def failed(self, now: float) -> float:
        """Note a failure at ``now``; return the seconds until the next try."""
        delay = min(self.first * 2.0**self.failures, self.maximum)
        self.failures += 1
        self.retry_at = now + delay
        return delay

    def succeeded(self) -> None:
        self.failures = 0
        self.retry_at = float("-inf")
