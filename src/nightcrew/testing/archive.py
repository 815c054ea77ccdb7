"""An image archive running in-process, for tests (and for the lead's integration tests).

::

    from nightcrew.testing.archive import running_archive

    async with running_archive(tmp_path) as archive:          # SQLite in tmp_path
        ...  # archive.url, archive.token, archive.server (the ArchiveServer)

    async with running_archive(tmp_path, database=cluster_dsn) as archive:   # PostgreSQL
        ...

With a PostgreSQL DSN, use a fresh database per archive
(:meth:`nightcrew.testing.postgres.PostgresCluster.create_database`). The archive listens on
127.0.0.1 and a free port and is closed when the block ends.
"""

from __future__ import annotations

import io
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.services.archive import ArchiveConfig, ArchiveServer, new_token

__all__ = ["RunningArchive", "fits_frame", "running_archive"]


@dataclass(frozen=True)
class RunningArchive:
    """A started archive: its base URL, upload token and server."""

    url: str
    token: str
    server: ArchiveServer

    @property
    def storage(self) -> Path:
        """The directory holding the frames."""
        return self.server.config.storage


@asynccontextmanager
async def running_archive(
    directory: Path, *, database: str | None = None, **options: Any
) -> AsyncIterator[RunningArchive]:
    """Start an archive storing under ``directory``; SQLite there unless ``database`` is a DSN.

    ``options`` are further :class:`ArchiveConfig` fields (``max_upload_bytes``, ...).
    """
    token = new_token()
    config = ArchiveConfig(
        storage=directory / "frames",
        database=database or f"sqlite:///{directory / 'archive.db'}",
        token=token,
        host="127.0.0.1",
        port=0,
        **options,
    )
    server = ArchiveServer(config)
    try:
        url = await server.start()
        yield RunningArchive(url, token, server)
    finally:
        await server.close()


def fits_frame(
    *,
    date_obs: str = "2026-11-24T20:00:00.000",
    instrument: str = "sbig6303",
    imagetyp: str = "object",
    exptime: float = 30.0,
    shape: tuple[int, int] = (32, 32),
    seed: int = 0,
    **cards: Any,
) -> bytes:
    """A small FITS frame with the required keywords and any further ``cards`` (``OBJECT="M 13"``,
    ``FILTER="V"``, ``RA=250.4``...; ``DATE_OBS``-style names with ``_`` become ``-``), its pixels
    seeded noise, so two seeds give two different files."""
    pixels = np.random.default_rng(seed).normal(1000.0, 10.0, shape).astype(np.uint16)
    header = fits.Header()
    header["DATE-OBS"] = date_obs
    header["INSTRUME"] = instrument
    header["IMAGETYP"] = imagetyp
    header["EXPTIME"] = exptime
    for key, value in cards.items():
        header[key.replace("_", "-")] = value
    out = io.BytesIO()
    fits.PrimaryHDU(pixels, header=header).writeto(out)
    return out.getvalue()
