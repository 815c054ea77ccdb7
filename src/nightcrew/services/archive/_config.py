"""The archive's configuration: a YAML file of plain keys, checked when it is loaded.

::

    host: 127.0.0.1                 # address to listen on
    port: 37190
    storage: /srv/archive/frames    # frames go to <storage>/<DAY-OBS>/<INSTRUME>/<basename>
    database: sqlite:///srv/archive/archive.db   # or postgresql://user@host:5432/archive
    token_file: /etc/nightcrew/archive.token     # or  token: ${NIGHTCREW_ARCHIVE_TOKEN}
    max_upload_bytes: 200000000     # larger uploads get 413
    max_zip_frames: 500             # frames one zip download may hold
    max_frame_pixels: 100000000     # frames declaring more pixels (NAXISn, ZNAXISn) get 422

The upload token comes from a file readable by its owner only (``nightcrew archive --new-token
FILE`` writes one) or from the environment through ``${...}``; it is never printed, and the repr
of :class:`ArchiveConfig` hides it.
"""

from __future__ import annotations

import os
import secrets
import stat
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from nightcrew.errors import ConfigError

__all__ = ["DEFAULT_PORT", "ArchiveConfig", "load_archive_config", "new_token", "write_new_token"]

DEFAULT_PORT = 37190
_KEYS = frozenset(
    {
        "host",
        "port",
        "storage",
        "database",
        "token",
        "token_file",
        "max_upload_bytes",
        "max_zip_frames",
        "max_frame_pixels",
    }
)
_MIN_TOKEN_CHARS = 16


@dataclass(frozen=True)
class ArchiveConfig:
    """Where the archive listens and keeps its frames and index.

    Args:
        storage: Directory of the frames (created if missing).
        database: ``sqlite:///PATH`` (relative paths: to the current directory) or
            ``postgresql://...`` (an asyncpg DSN).
        token: The bearer token uploads must carry (at least 16 characters).
        host: Address to listen on.
        port: Port to listen on (0: a free one).
        max_upload_bytes: The largest upload accepted.
        max_zip_frames: The most frames one zip download may hold.
        max_frame_pixels: The most pixels a stored frame's image may declare (its NAXISn, or
            ZNAXISn when tile-compressed: a small file may claim a huge image).
        sqlite_busy_timeout: Seconds SQLite waits for a lock before the request gets 503.
    """

    storage: Path
    database: str
    token: str = field(repr=False)
    host: str = "127.0.0.1"
    port: int = DEFAULT_PORT
    max_upload_bytes: int = 200_000_000
    max_zip_frames: int = 500
    max_frame_pixels: int = 100_000_000
    sqlite_busy_timeout: float = 5.0

    def __post_init__(self) -> None:
        if not self.database.startswith(("sqlite:///", "postgresql://", "postgres://")):
            raise ConfigError(
                f"must be sqlite:///PATH or postgresql://..., got {self.database!r}", key="database"
            )
        if len(self.token) < _MIN_TOKEN_CHARS:
            raise ConfigError(
                f"the upload token must have at least {_MIN_TOKEN_CHARS} characters", key="token"
            )
        if not 0 <= self.port <= 65535:
            raise ConfigError(f"must be 0..65535, got {self.port}", key="port")
        if self.max_upload_bytes < 2880:
            raise ConfigError(
                f"must be at least one FITS block (2880), got {self.max_upload_bytes}", key="max_upload_bytes"
            )
        if self.max_zip_frames < 1:
            raise ConfigError(f"must be >= 1, got {self.max_zip_frames}", key="max_zip_frames")
        if self.max_frame_pixels < 1:
            raise ConfigError(f"must be >= 1, got {self.max_frame_pixels}", key="max_frame_pixels")

    @property
    def dialect(self) -> str:
        """``sqlite`` or ``postgresql``."""
        return "sqlite" if self.database.startswith("sqlite:") else "postgresql"


def load_archive_config(config: Mapping[str, Any], *, file: str | None = None) -> ArchiveConfig:
    """Build an ArchiveConfig from a loaded YAML mapping; a bad key fails naming file and key."""
    unknown = sorted(set(config) - _KEYS)
    if unknown:
        raise ConfigError(
            f"unknown key {unknown[0]!r} (known: {', '.join(sorted(_KEYS))})", file=file, key=unknown[0]
        )
    for key in ("storage", "database"):
        if not isinstance(config.get(key), str) or not config[key]:
            raise ConfigError("a path or URL is required", file=file, key=key)
    token = _token(config, file)
    try:
        return ArchiveConfig(
            storage=Path(config["storage"]),
            database=str(config["database"]),
            token=token,
            host=str(config.get("host", "127.0.0.1")),
            port=_integer(config, "port", DEFAULT_PORT, file),
            max_upload_bytes=_integer(config, "max_upload_bytes", 200_000_000, file),
            max_zip_frames=_integer(config, "max_zip_frames", 500, file),
            max_frame_pixels=_integer(config, "max_frame_pixels", 100_000_000, file),
        )
    except ConfigError as exc:
        raise ConfigError(exc.message, file=file, key=exc.key) from None


def _integer(config: Mapping[str, Any], key: str, default: int, file: str | None) -> int:
    value = config.get(key, default)
    if not isinstance(value, int) or isinstance(value, bool):
        raise ConfigError(f"must be an integer, got {value!r}", file=file, key=key)
    return value


def _token(config: Mapping[str, Any], file: str | None) -> str:
    if ("token" in config) == ("token_file" in config):
        raise ConfigError(
            "give exactly one of token (e.g. ${NIGHTCREW_ARCHIVE_TOKEN}) and token_file",
            file=file,
            key="token",
        )
    if "token" in config:
        return str(config["token"])
    path = Path(str(config["token_file"]))
    try:
        mode = path.stat().st_mode
        token = path.read_text().strip()
    except OSError as exc:
        raise ConfigError(f"cannot read {path}: {exc.strerror}", file=file, key="token_file") from None
    if mode & (stat.S_IRWXG | stat.S_IRWXO):
        raise ConfigError(f"{path} is readable by others: chmod 600 it", file=file, key="token_file")
    return token


def new_token() -> str:
    """A fresh random upload token (256 bits)."""
    return secrets.token_urlsafe(32)


def write_new_token(path: Path) -> None:
    """Write a fresh random token to ``path``, readable by its owner only (refuses to overwrite)."""
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(descriptor, "w") as out:
        out.write(new_token() + "\n")
