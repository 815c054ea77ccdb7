"""Pipeline: the online reduction — every new science frame reduced while the night goes on.

On each NewImageEvent of an object frame it reads the frame through its VFS, calibrates it with
the newest fitting masters from ``masters`` (the directory is listed again for each frame, so
masters made during the night are used at once), detects its stars, plate-solves them (the
catalog matcher, then the solve service at ``solver_url``, then optionally solve-field), measures
aperture photometry and writes ``<output>/<raw name>_red.fits`` with ``RLEVEL`` = 91, ``RAWFILE``
and ``BIASFILE``/``DARKFILE``/``FLATFILE`` (see :func:`nightcrew.images.reduce.reduce_frame`, the
code ``nightcrew reduce`` runs too). With an ArchiveFile root as ``output`` the reduced frames go
to the archive. A frame taken while following a moving body also gets the body's measured position
(``MOV-*`` cards) and, beside the reduced frame, ``<raw name>_red.mpc`` with its MPC 80-column line.
Frames wait in a queue and are reduced one at a time.
"""

from __future__ import annotations

import asyncio
import logging
import posixpath
from typing import Any

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import NewImageEvent
from nightcrew.images.calibration import (
    CalibrationCache,
    MasterInfo,
    MasterKind,
    frame_key,
    master_kind,
    select_master,
)
from nightcrew.images.image import Image
from nightcrew.images.processors.moving import mpc_line_of
from nightcrew.images.reduce import Master, ReductionSteps, StageTimes, reduce_frame
from nightcrew.interfaces import ImageType, ModuleState
from nightcrew.modules.module import Module

__all__ = ["Pipeline"]

log = logging.getLogger(__name__)

_FITS = (".fits", ".fit", ".fits.gz")


class Pipeline(Module):
    """Reduces every new object frame (see the module docstring).

    Args:
        masters: VFS directory of master frames (``nightcrew reduce`` writes them to ``OUT/masters``).
        output: VFS directory for the reduced frames.
        solver_url: The plate-solving service (``nightcrew solver``); None: catalog matcher only
            (plus solve-field when ``solve_field``).
        solve_field: Fall back to astrometry.net's solve-field (slow: seconds to a minute).
        index_dir: The astrometry.net index files of the catalog matcher and solve-field; None:
            the system's (``/usr/share/astrometry``).
        pixel_scale_arcsec: Unbinned pixel scale; None: from the headers.
        sources: Only frames from these modules (cameras); all by default.
        max_queue: Frames waiting at most; more are dropped with an error (the night goes on).
        observatory_code: The site's MPC observatory code in the MPC lines of moving bodies
            (``XXX`` until the MPC assigns one).
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        masters: str,
        output: str,
        solver_url: str | None = None,
        solve_field: bool = False,
        index_dir: str | None = None,
        pixel_scale_arcsec: float | None = None,
        sources: list[str] | None = None,
        max_queue: int = 100,
        observatory_code: str = "XXX",
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        for key, value in (("masters", masters), ("output", output)):
            if not isinstance(value, str) or not value.startswith("/"):
                raise ConfigError(f"must be an absolute VFS path, got {value!r}", key=key)
        if solver_url is not None and not solver_url.startswith(("http://", "https://")):
            raise ConfigError(f"must be an http:// or https:// URL, got {solver_url!r}", key="solver_url")
        if pixel_scale_arcsec is not None and not pixel_scale_arcsec > 0:
            raise ConfigError(f"must be positive, got {pixel_scale_arcsec}", key="pixel_scale_arcsec")
        if sources is not None and not sources:
            raise ConfigError("name at least one module, or leave sources out", key="sources")
        if max_queue < 1:
            raise ConfigError(f"must be >= 1, got {max_queue}", key="max_queue")
        if not (isinstance(observatory_code, str) and len(observatory_code) == 3):
            raise ConfigError(f"three characters, got {observatory_code!r}", key="observatory_code")
        self._observatory_code = observatory_code
        self._masters = masters.rstrip("/")
        self._output = output.rstrip("/") or "/"
        self._sources = set(sources) if sources is not None else None
        self._steps = ReductionSteps.default(
            pixel_scale_arcsec=pixel_scale_arcsec,
            index_dir=index_dir,
            solver_url=solver_url,
            solve_field=solve_field,
        )
        self._queue: asyncio.Queue[str] = asyncio.Queue(max_queue)
        self._master_infos: dict[str, MasterInfo | None] = {}  # by path; None: not a master
        self._master_images: CalibrationCache[Image] = CalibrationCache(8)
        self.times = StageTimes()
        self.reduced: list[str] = []  # VFS paths written, oldest first (for status and tests)
        self.failed: list[str] = []  # raw frames that could not be reduced
        self.add_background_task(self._reduce_loop)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        if self._sources is not None and sender not in self._sources:
            return
        if event.image_type is not ImageType.OBJECT:
            return
        try:
            self._queue.put_nowait(event.filename)
        except asyncio.QueueFull:
            log.error("%s: %d frames waiting; dropped %s", self.name, self._queue.qsize(), event.filename)
            self.failed.append(event.filename)

    async def _reduce_loop(self) -> None:
        while True:
            path = await self._queue.get()
            try:
                self.reduced.append(await self.reduce(path))
            except NightcrewError as exc:
                log.error("%s: reducing %s failed: %s", self.name, path, exc)
                self.failed.append(path)
            finally:
                self._queue.task_done()

    async def reduce(self, path: str) -> str:
        """Reduce the raw frame at VFS ``path``; return the reduced frame's VFS path."""
        raw = await Image.from_vfs(self.vfs, path)
        key = frame_key(raw.header)
        library = await self._library()
        bias, dark, flat = [
            await self._master(select_master(library, kind, key))
            for kind in (MasterKind.BIAS, MasterKind.DARK, MasterKind.FLAT)
        ]
        raw_name = posixpath.basename(path)
        image, notes = await reduce_frame(
            raw, raw_name=raw_name, steps=self._steps, bias=bias, dark=dark, flat=flat, times=self.times
        )
        target = posixpath.join(self._output, raw_name.split(".fit")[0] + "_red.fits")
        await image.to_vfs(self.vfs, target)
        line = mpc_line_of(image.header, self._observatory_code)
        if line is not None:
            await self.vfs.write_bytes(target.removesuffix(".fits") + ".mpc", (line + "\n").encode())
        log.info("%s: reduced %s to %s%s", self.name, path, target, f" ({'; '.join(notes)})" if notes else "")
        return target

    async def _library(self) -> list[MasterInfo]:
        """The masters in the directory now; headers of files seen before are not read again."""
        names = [n for n in await self.vfs.listdir(self._masters) if n.lower().endswith(_FITS)]
        for name in names:
            path = f"{self._masters}/{name}"
            if path not in self._master_infos:
                try:
                    image = await Image.from_vfs(self.vfs, path)
                except NightcrewError:
                    self._master_infos[path] = None  # not every file there must be a master
                    continue
                kind = master_kind(image)
                self._master_infos[path] = (
                    None if kind is None else MasterInfo(path, kind, frame_key(image.header))
                )
                if kind is not None:
                    self._master_images.put(path, image)
        present = {f"{self._masters}/{name}" for name in names}
        return [info for path, info in self._master_infos.items() if info is not None and path in present]

    async def _master(self, info: MasterInfo | None) -> Master | None:
        if info is None:
            return None
        image = self._master_images.get(info.path)
        if image is None:
            image = await Image.from_vfs(self.vfs, info.path)
            self._master_images.put(info.path, image)
        return Master(posixpath.basename(info.path), image)
