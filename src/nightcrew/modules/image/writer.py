"""ImageWriter: keeps a copy of every new image under a path made from its FITS header.

On a NewImageEvent it reads the file through its own VFS (the path is the sender's), names the
copy with the camera's filename-pattern rules (``/archive/{DATE-OBS}-{IMAGETYP}.fits``), writes it
atomically and checks the copy's checksum.

Copies are made one at a time, in the order the images came. A copy that fails because the
original or the destination cannot be reached (server stopped, link down, a copy that differs)
waits and is tried again after ``retry_delay`` clock seconds, doubling up to ``max_retry_delay``;
images that come meanwhile wait behind it. Only a copy that cannot succeed (the original is gone
or is not a FITS file, or the destination refuses its content, as an archive refuses a frame
without its required keywords) is dropped, with an error in the log; the original stays where it is.

Events are not stored: one sent while the writer was down (killed, restarting) or cut off from
the server never reaches it. With ``sweep`` (a glob of the originals, e.g. ``/images/*.fits``)
the writer also lists the originals every ``sweep_interval`` clock seconds, and after a start,
and copies those it has not copied yet; which ones it has is kept in ``state_file`` (written
after every copy, so it survives ``kill -9``).
"""

from __future__ import annotations

import asyncio
import hashlib
import io
import json
import logging
import os
from typing import Any

from nightcrew.config import DataPath
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import NewImageEvent
from nightcrew.interfaces import FitsValue, ImageType, ModuleState
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.image.watch_state import Backoff
from nightcrew.modules.module import Module
from nightcrew.vfs import LocalFile, VfsError, VfsFileNotFoundError, VfsFormatError
from nightcrew.vfs.filenames import check_filename_pattern, format_filename

__all__ = ["ImageWriter", "read_header"]

log = logging.getLogger(__name__)


def read_header(data: bytes) -> dict[str, FitsValue]:
    """The primary header of the FITS file ``data`` as keyword → value."""
    from astropy.io import fits  # type: ignore[import-untyped]

    header = fits.Header.fromfile(io.BytesIO(data))
    return {key: value for key, value in header.items() if isinstance(value, bool | int | float | str)}


class ImageWriter(Module):
    """Copies every new image to ``pattern``.

    Args:
        pattern: VFS path of the copy; placeholders are FITS keywords of the image, e.g.
            ``/archive/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits`` (a missing keyword gives ``none``).
        sources: Only images from these modules (cameras); all by default.
        image_types: Only images of these types (object, flat ...); all by default.
        retry_delay: Clock seconds before a failed copy is tried again (doubles each time).
        max_retry_delay: The longest wait between tries.
        sweep: VFS glob of the originals to look through for images without a copy (those whose
            events were missed); None: copy on events only.
        sweep_interval: Clock seconds between two sweeps.
        state_file: Local file naming the originals copied; required with ``sweep``.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        pattern: str,
        sources: list[str] | None = None,
        image_types: list[ImageType] | None = None,
        retry_delay: float = 5.0,
        max_retry_delay: float = 120.0,
        sweep: str | None = None,
        sweep_interval: Period = 60.0,
        state_file: DataPath | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        check_filename_pattern(pattern, key="pattern")
        if sources is not None and not sources:
            raise ConfigError("name at least one module, or leave sources out", key="sources")
        if not 0 < retry_delay <= max_retry_delay:
            raise ConfigError("need 0 < retry_delay <= max_retry_delay", key="retry_delay")
        if sweep is not None and not sweep.startswith("/"):
            raise ConfigError(f"must be a VFS glob like /images/*.fits, got {sweep!r}", key="sweep")
        if sweep is not None and not state_file:
            raise ConfigError("a sweep needs a state_file to remember the copies made", key="state_file")
        if not sweep_interval > 0:
            raise ConfigError(f"must be > 0 seconds, got {sweep_interval}", key="sweep_interval")
        self._pattern = pattern
        self._sources = set(sources) if sources is not None else None
        self._image_types = {ImageType(t) for t in image_types} if image_types else None
        self.written: list[str] = []  # paths of the copies made, oldest first (for status and tests)
        self._waiting: list[str] = []  # originals to copy, oldest first
        self._arrived = asyncio.Event()
        self._backoff = Backoff(retry_delay, max_retry_delay)
        self._sweep, self._sweep_interval = sweep, float(sweep_interval)
        self._copied: set[str] = set()  # originals copied (only kept with a sweep)
        self._state_store: tuple[LocalFile, str] | None = None
        if state_file:
            path = os.path.abspath(state_file)
            self._state_store = (LocalFile(os.path.dirname(path)), os.path.basename(path))  # atomic writes
        self.add_background_task(self._copy_loop)
        if sweep is not None:
            self.add_background_task(self._sweep_loop)

    @property
    def waiting(self) -> int:
        """How many images wait for their copy."""
        return len(self._waiting)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        if self._state_store is not None:
            try:
                self._copied = set(json.loads(await self._state_store[0].read_bytes(self._state_store[1])))
            except VfsFileNotFoundError:
                pass  # first start
            except (VfsError, ValueError, TypeError) as exc:
                log.warning("%s: ignoring unreadable state (%s); copies may be repeated", self.name, exc)
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)

    async def close(self) -> None:
        if self._waiting:
            log.warning(
                "%s: stopping with %d images not copied: %s", self.name, len(self._waiting), self._waiting
            )
        await super().close()

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        if self._sources is not None and sender not in self._sources:
            return
        if self._image_types is not None and event.image_type not in self._image_types:
            return
        self._enqueue(event.filename)

    def _enqueue(self, path: str) -> None:
        if path not in self._waiting:
            self._waiting.append(path)
            self._arrived.set()

    async def _sweep_loop(self) -> None:
        assert self._sweep is not None
        while True:
            try:
                present = await self.vfs.find(self._sweep)
            except NightcrewError as exc:
                log.warning("%s: cannot look through %s: %s", self.name, self._sweep, exc)
            else:
                self._copied &= set(present)  # forget originals that are gone (evicted, moved)
                for path in present:
                    if path not in self._copied:
                        self._enqueue(path)
            await self.clock.sleep(self._sweep_interval)

    async def _done(self, path: str) -> None:
        """``path`` needs no more copying: remember it (with a sweep) and save the state."""
        self._waiting.remove(path)
        if self._state_store is None:
            return
        self._copied.add(path)
        try:
            await self._state_store[0].write_bytes(
                self._state_store[1], json.dumps(sorted(self._copied)).encode()
            )
        except VfsError as exc:
            log.error("%s: cannot save the state: %s", self.name, exc)

    async def _copy_loop(self) -> None:
        while True:
            if not self._waiting:
                self._arrived.clear()
                await self._arrived.wait()
                continue
            wait = self._backoff.retry_at - self.clock.time()
            if wait > 0:
                await self.clock.sleep(wait)
            path = self._waiting[0]
            try:
                data = await self.vfs.read_bytes(path)
                header = _header_of(data)
                await self._store(data, header)
            except (VfsFileNotFoundError, VfsFormatError, _NotAnImage) as exc:
                log.error("%s: cannot copy %s: %s", self.name, path, exc)
            except NightcrewError as exc:
                delay = self._backoff.failed(self.clock.time())
                log.warning(
                    "%s: copying %s failed: %s; trying again in %.0f s (%d waiting)",
                    self.name, path, exc, delay, len(self._waiting),
                )  # fmt: skip
                continue
            else:
                self._backoff.succeeded()
            await self._done(path)

    async def write_copy(self, path: str) -> str:
        """Copy the image at VFS ``path`` to its place under the pattern; return the new path."""
        data = await self.vfs.read_bytes(path)
        try:
            header = _header_of(data)
        except _NotAnImage as exc:
            raise VfsError(str(exc), path=path) from exc
        return await self._store(data, header)

    async def _store(self, data: bytes, header: dict[str, FitsValue]) -> str:
        target = format_filename(self._pattern, header)
        await self.vfs.write_bytes(target, data)
        if await self.vfs.checksum(target) != hashlib.sha256(data).hexdigest():
            raise VfsError("the copy differs from the original after writing", path=target)
        log.info("%s: wrote %s", self.name, target)
        self.written.append(target)
        return target


class _NotAnImage(Exception):  # not a NightcrewError: never on the wire, only a reason to give up
    """The original is no FITS file: trying again cannot help."""


def _header_of(data: bytes) -> dict[str, FitsValue]:
    try:
        return read_header(data)
    except Exception as exc:  # astropy raises many kinds for a broken file
        raise _NotAnImage(f"not a FITS file: {exc}") from exc
