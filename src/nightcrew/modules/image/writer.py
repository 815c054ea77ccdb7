"""ImageWriter: keeps a copy of every new image under a path made from its FITS header.

On a NewImageEvent it reads the file through its own VFS (the path is the sender's), names the
copy with the camera's filename-pattern rules (``/archive/{DATE-OBS}-{IMAGETYP}.fits``), writes it
atomically and checks the copy's checksum.
"""

from __future__ import annotations

import hashlib
import io
import logging
from typing import Any

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import NewImageEvent
from nightcrew.interfaces import FitsValue, ImageType, ModuleState
from nightcrew.modules.module import Module
from nightcrew.vfs import VfsError
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
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        pattern: str,
        sources: list[str] | None = None,
        image_types: list[ImageType] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        check_filename_pattern(pattern, key="pattern")
        if sources is not None and not sources:
            raise ConfigError("name at least one module, or leave sources out", key="sources")
        self._pattern = pattern
        self._sources = set(sources) if sources is not None else None
        self._image_types = {ImageType(t) for t in image_types} if image_types else None
        self.written: list[str] = []  # paths of the copies made, oldest first (for status and tests)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        await self.comm.register_event(NewImageEvent, self.on_new_image)

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        if self._sources is not None and sender not in self._sources:
            return
        if self._image_types is not None and event.image_type not in self._image_types:
            return
        try:
            await self.write_copy(event.filename)
        except NightcrewError as exc:
            log.error("%s: copying %s failed: %s", self.name, event.filename, exc)

    async def write_copy(self, path: str) -> str:
        """Copy the image at VFS ``path`` to its place under the pattern; return the new path."""
        data = await self.vfs.read_bytes(path)
        try:
            header = read_header(data)
        except Exception as exc:  # astropy raises many kinds for a broken file
            raise VfsError(f"not a FITS file: {exc}", path=path) from exc
        target = format_filename(self._pattern, header)
        await self.vfs.write_bytes(target, data)
        if await self.vfs.checksum(target) != hashlib.sha256(data).hexdigest():
            raise VfsError("the copy differs from the original after writing", path=target)
        log.info("%s: wrote %s", self.name, target)
        self.written.append(target)
        return target
