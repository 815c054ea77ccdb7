"""``nightcrew sim --archive``: the night's frames reduced as they come and kept in an image archive.

During the night a :class:`~nightcrew.modules.image.Pipeline` reduces every object frame of the
camera into ``--out/reduced`` (masters from ``--out/masters``, listed again for each frame). When
the night has ended and the pipeline has reduced every frame it was given, an archive
(``nightcrew archive``: SQLite ``--out/archive/archive.db``, frames in ``--out/archive/frames``)
is started on a real-time loop, every raw and every reduced frame is copied into it through the
``ArchiveFile`` VFS root and verified by the archive's checksum (copies only: the sim's own frames
stay), and ``--out/archive/archive.yaml`` is written for ``nightcrew archive --config`` to browse
it afterwards. The upload waits for the night's end because a night on the virtual clock may not
wait on a real server's replies (docs/concepts.md#clock); uploading ~220 frames takes seconds.
"""

from __future__ import annotations

import asyncio
import hashlib
import shutil
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from nightcrew.clock import Clock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.errors import NightcrewError
from nightcrew.modules import Module
from nightcrew.modules.image import Pipeline
from nightcrew.night.build import CAMERA, IMAGES_ROOT
from nightcrew.night.engine import FRAMES
from nightcrew.services.archive import DEFAULT_PORT, ArchiveServer, load_archive_config, write_new_token
from nightcrew.vfs import ArchiveFile, LocalFile, VirtualFileSystem

__all__ = [
    "ARCHIVE",
    "MASTERS",
    "REDUCED",
    "ArchivedNight",
    "NightPipeline",
    "archive_and_show",
    "archive_night",
    "clear_archive_products",
    "sim_pipeline",
]

#: Directories in ``--out``: the archive (database, frames, config, token), reduced frames, masters.
ARCHIVE, REDUCED, MASTERS = "archive", "reduced", "masters"
#: The VFS root of ``--out`` in the pipeline's VFS.
_NIGHT_ROOT = "night"
#: Clock seconds the pipeline may take per frame still waiting when the night ends.
_DRAIN_S_PER_FRAME = 300.0


class NightPipeline(Pipeline):
    """The Pipeline that, when closed, first reduces every frame still waiting (bounded)."""

    async def close(self) -> None:
        waiting = self._queue.qsize() + 1  # +1: the frame being reduced now
        try:
            async with self.clock.timeout(_DRAIN_S_PER_FRAME * waiting):
                await self._queue.join()
        except TimeoutError:
            self.failed.append(f"{self._queue.qsize()} frames not reduced by the night's end")
        await super().close()


def clear_archive_products(out: Path) -> None:
    """Remove the reduced frames and the archive of an earlier night in ``out``; make the dirs."""
    shutil.rmtree(out / ARCHIVE, ignore_errors=True)
    for name in (REDUCED, MASTERS):
        (out / name).mkdir(parents=True, exist_ok=True)
    for old in (out / REDUCED).glob("*.fits"):
        old.unlink()


def sim_pipeline(out: Path, *, clock: Clock) -> Callable[[LocalNetwork], list[Module]]:
    """What ``--archive`` adds to the night: a NightPipeline reducing the camera's object frames."""

    def build(network: LocalNetwork) -> list[Module]:
        vfs = VirtualFileSystem({IMAGES_ROOT: LocalFile(str(out / FRAMES)), _NIGHT_ROOT: LocalFile(str(out))})
        pipeline = NightPipeline(
            masters=f"/{_NIGHT_ROOT}/{MASTERS}",
            output=f"/{_NIGHT_ROOT}/{REDUCED}",
            sources=[CAMERA],
            comm=LocalComm("pipeline", network=network),
            clock=clock,
            vfs=vfs,
        )
        return [pipeline]

    return build


@dataclass
class ArchivedNight:
    """What went into the archive, and how to open it again."""

    config: Path
    database: Path
    storage: Path
    raw: list[str] = field(default_factory=list)
    reduced: list[str] = field(default_factory=list)
    failed: list[str] = field(default_factory=list)  # "<file>: <why>"


def archive_and_show(out: Path) -> bool:
    """Copy the night into its archive and say where it is; False when a frame did not go in."""
    archived = archive_night(out)
    raw, reduced = len(archived.raw), len(archived.reduced)
    print(
        f"  archive: {raw} raw and {reduced} reduced frames in {archived.storage} "
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
        for folder, names in ((FRAMES, result.raw), (REDUCED, result.reduced)):
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
