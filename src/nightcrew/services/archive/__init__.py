"""The image archive: frames stored by date and instrument, headers indexed, searched over HTTP.

:class:`ArchiveServer` runs it (``nightcrew archive --config FILE``); :class:`ArchiveConfig` is its
configuration (:func:`load_archive_config` reads a YAML mapping). The HTTP API follows the LCO
science archive's ``/frames/`` (docs/archive.md); :class:`nightcrew.vfs.ArchiveFile` is its
client as a VFS root. Databases: SQLite (default, stdlib) or PostgreSQL (asyncpg), one schema with
versioned migrations for both.
"""

from nightcrew.services.archive._config import (
    DEFAULT_PORT,
    ArchiveConfig,
    load_archive_config,
    new_token,
    write_new_token,
)
from nightcrew.services.archive._fits import REDUCED, REQUIRED
from nightcrew.services.archive._server import ArchiveServer

__all__ = [
    "DEFAULT_PORT",
    "REDUCED",
    "REQUIRED",
    "ArchiveConfig",
    "ArchiveServer",
    "load_archive_config",
    "new_token",
    "write_new_token",
]
