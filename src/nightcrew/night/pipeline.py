"""The online reduction of ``nightcrew sim --archive``: masters and reduced frames while the night runs.

:class:`NightPipeline` is the :class:`~nightcrew.modules.image.Pipeline` with two additions the
sim needs. It notes the camera's bias, dark and flat frames, and before it reduces an object
frame it builds the masters of every calibration group not yet built (the groups and the
combination of ``nightcrew reduce``: :func:`~nightcrew.images.reduce.group_frames`,
:func:`~nightcrew.images.calibration.build_master`) into ``--out/masters``, where the Pipeline
finds them; a group is built once, from the frames taken until then (the sim takes its
calibration frames in one series). And when it is closed at the night's end it first reduces
every frame still waiting, so no frame of the night goes unreduced, then builds the masters of
calibration frames no object frame came after (the morning's darks), for the archive.
"""

from __future__ import annotations

import asyncio
import logging
from pathlib import Path
from typing import Any

from nightcrew.config import DataPath
from nightcrew.errors import NightcrewError
from nightcrew.events import NewImageEvent
from nightcrew.images.calibration import MasterInfo, MasterKind, build_master, frame_key, select_master
from nightcrew.images.image import Image
from nightcrew.images.reduce import GroupKey, group_frames, read_entry
from nightcrew.interfaces import ImageType
from nightcrew.modules.image import Pipeline
from nightcrew.night.build import CAMERA
from nightcrew.night.engine import FRAMES

__all__ = ["MASTERS", "REDUCED", "NightPipeline"]

log = logging.getLogger(__name__)

#: Directories in ``--out``: reduced frames, masters.
REDUCED, MASTERS = "reduced", "masters"
#: Clock seconds the pipeline may take per frame still waiting when the night ends.
_DRAIN_S_PER_FRAME = 300.0
_CALIBRATION = (ImageType.BIAS, ImageType.DARK, ImageType.SKYFLAT, ImageType.DOMEFLAT)


class NightPipeline(Pipeline):
    """The Pipeline building the night's masters as it goes (see the module docstring).

    Args:
        out: The sim's output directory (frames in ``out/frames``, masters to ``out/masters``).
        **kwargs: Pipeline options.
    """

    def __init__(self, *, out: DataPath, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._frames, self._masters_dir = Path(out) / FRAMES, Path(out) / MASTERS
        self._calibration_frames: list[Path] = []
        self._built: dict[GroupKey, Image] = {}

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        if sender == CAMERA and event.image_type in _CALIBRATION:
            # The event's path is the camera's VFS path /images/<name>; the file is in out/frames.
            self._calibration_frames.append(self._frames / event.filename.rsplit("/", 1)[-1])
        await super().on_new_image(event, sender)

    async def reduce(self, path: str) -> str:
        await self._build_masters()
        return await super().reduce(path)

    async def _build_masters(self) -> None:
        if self._calibration_frames:
            frames, self._calibration_frames = self._calibration_frames, []
            written = await asyncio.to_thread(_blocking_build_masters, frames, self._masters_dir, self._built)
            for name in written:
                log.info("%s: built %s", self.name, name)

    async def close(self) -> None:
        waiting = self._queue.qsize() + 1  # +1: the frame being reduced now
        try:
            async with self.clock.timeout(_DRAIN_S_PER_FRAME * waiting):
                await self._queue.join()
        except TimeoutError:
            log.error("%s: %d frames not reduced by the night's end", self.name, self._queue.qsize())
        try:
            await (
                self._build_masters()
            )  # e.g. the darks of the morning: no frame used them, the archive keeps them
        except NightcrewError as exc:
            log.error("%s: building the last masters failed: %s", self.name, exc)
        await super().close()


def _blocking_build_masters(frames: list[Path], directory: Path, built: dict[GroupKey, Image]) -> list[str]:
    """Build the masters of the groups of ``frames`` not in ``built`` into ``directory`` (biases
    first: darks and flats need them); add them to ``built``; the file names written."""
    groups = group_frames(read_entry(path) for path in frames)
    written = []
    for key in sorted(groups):  # roles sort bias, dark, flat
        if key in built:
            continue
        images = [Image.from_bytes(entry.path.read_bytes()) for entry in groups[key]]
        library = [MasterInfo(str(k), k.master_kind, frame_key(m.header)) for k, m in built.items()]
        by_name = {str(k): m for k, m in built.items()}
        first = frame_key(images[0].header)
        bias = select_master(library, MasterKind.BIAS, first)
        dark = select_master(library, MasterKind.DARK, first) if key.master_kind is MasterKind.FLAT else None
        try:
            master = build_master(
                key.master_kind,
                images,
                bias=None if bias is None else by_name[bias.path],
                dark=None if dark is None else by_name[dark.path],
            )
        except NightcrewError as exc:  # e.g. darks without biases: reduce without that master
            log.warning("no %s: %s", key.file_name, exc)
            continue
        (directory / key.file_name).write_bytes(master.to_bytes())
        built[key] = master
        written.append(key.file_name)
    return written
