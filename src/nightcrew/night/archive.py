"""``nightcrew sim --archive``: the night's frames, masters and reduced frames in an image archive.

During the night a :class:`~nightcrew.night.pipeline.NightPipeline` builds masters into
``--out/masters`` and reduces every object frame of the camera into ``--out/reduced``. When the
night has ended and every frame is reduced, an archive (``nightcrew archive``: SQLite
``--out/archive/archive.db``, frames in ``--out/archive/frames``) is started on a real-time loop;
every raw frame, master and reduced frame is copied into it through the ``ArchiveFile`` VFS root
and verified by the archive's checksum (copies only: the sim's own files stay), and
``--out/archive/archive.yaml`` is written for ``nightcrew archive --config`` to browse it
afterwards. The upload waits for the night's end because a night on the virtual clock may not wait
on a real server's replies (docs/concepts.md#clock); uploading a whole night takes seconds.
"""

from __future__ import annotations

import asyncio
import hashlib
import shutil
import sys
from dataclasses import dataclass, field
from pathlib import Path

from nightcrew.errors import NightcrewError
from nightcrew.night.engine import FRAMES
from nightcrew.night.pipeline import MASTERS, REDUCED
from nightcrew.services.archive import DEFAULT_PORT, ArchiveServer, load_archive_config, write_new_token
from nightcrew.vfs import ArchiveFile, LocalFile, VirtualFileSystem

__all__ = [
    "ARCHIVE",
    "ArchivedNight",
    "archive_and_show",
    "archive_night",
    "clear_archive_products",
]

#: The archive's directory in ``--out``: database, frames, config, token.
ARCHIVE = "archive"
#: The VFS root of ``--out`` in the uploader's VFS.
_NIGHT_ROOT = "night"


def clear_archive_products(out: Path) -> None:
    """Remove the reduced frames and the archive of an earlier night in ``out``; make the dirs."""
    shutil.rmtree(out / ARCHIVE, ignore_errors=True)
    for name in (REDUCED, MASTERS):
        (out / name).mkdir(parents=True, exist_ok=True)
    for old in [*(out / REDUCED).glob("*.fits"), *(out / MASTERS).glob("*.fits")]:
        old.unlink()


@dataclass
class ArchivedNight:
    """What went into the archive, and how to open it again."""

    config: Path
    database: Path
    storage: Path
    raw: list[str] = field(default_factory=list)
    masters: list[str] = field(default_factory=list)
    reduced: list[str] = field(default_factory=list)
    failed: list[str] = field(default_factory=list)  # "<file>: <why>"


def archive_and_show(out: Path) -> bool:
    """Copy the night into its archive and say where it is; False when a frame did not go in."""
    archived = archive_night(out)
    raw, masters, reduced = len(archived.raw), len(archived.masters), len(archived.reduced)
    print(
        f"  archive: {raw} raw frames, {masters} masters, {reduced} reduced frames in {archived.storage} "
        f"(SQLite {archived.database})"
    )
    print(
        f"  browse it: nightcrew archive --config {archived.config}  (then http://127.0.0.1:{DEFAULT_PORT}/)"
    )
    for failure in archived.failed:
        print(f"  not archived: {failure}", file=sys.stderr)
    return not archived.failed


def archive_night(out: Path) -> ArchivedNight:
    """Start an archive in ``out/archive`` and copy the night's raw and reduced frames into it."""
    return asyncio.run(_archive_night(out))


async def _archive_night(out: Path) -> ArchivedNight:
    directory = (out / ARCHIVE).resolve()
    directory.mkdir(parents=True, exist_ok=True)
    token_file = directory / "archive.token"
    write_new_token(token_file)
    result = ArchivedNight(
        config=directory / "archive.yaml", database=directory / "archive.db", storage=directory / "frames"
    )
    settings = {
        "storage": str(result.storage),
        "database": f"sqlite:///{result.database}",
        "token_file": str(token_file),
        "host": "127.0.0.1",
    }
    result.config.write_text(
        "".join(f"{key}: {value}\n" for key, value in settings.items()), encoding="utf-8"
    )
    server = ArchiveServer(load_archive_config({**settings, "port": 0}, file=str(result.config)))
    url = await server.start()
    token = token_file.read_text(encoding="utf-8").strip()
    vfs = VirtualFileSystem({_NIGHT_ROOT: LocalFile(str(out)), ARCHIVE: ArchiveFile(url, token=token)})
    try:
        for folder, names in ((FRAMES, result.raw), (MASTERS, result.masters), (REDUCED, result.reduced)):
            for path in sorted((out / folder).glob("*.fits")):
                why = await _copy(vfs, f"/{_NIGHT_ROOT}/{folder}/{path.name}", f"/{ARCHIVE}/{path.name}")
                if why is None:
                    names.append(path.name)
                else:
                    result.failed.append(f"{folder}/{path.name}: {why}")
    finally:
        await vfs.close()
        await server.close()
    return result


async def _copy(vfs: VirtualFileSystem, source: str, target: str) -> str | None:
    """Copy ``source`` to ``target`` and check the archive's checksum; None, or what went wrong."""
    try:
        data = await vfs.read_bytes(source)
        await vfs.write_bytes(target, data)
        stored = await vfs.checksum(target)
    except NightcrewError as exc:
        return str(exc)
    expected = hashlib.sha256(data).hexdigest()
    return None if stored == expected else f"the archive holds sha256 {stored}, the file has {expected}"
