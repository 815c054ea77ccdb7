"""The calibration processor: masters from a VFS directory, chosen per frame and cached."""

from __future__ import annotations

import asyncio
from typing import Any

from nightcrew.images.calibration._images import calibrate_image, master_kind
from nightcrew.images.calibration._library import (
    CalibrationCache,
    FrameKey,
    MasterInfo,
    MasterKind,
    frame_key,
    select_master,
)
from nightcrew.images.errors import ImageError, ImageFormatError
from nightcrew.images.image import Image
from nightcrew.images.processor import ImageProcessor, require

__all__ = ["Calibration", "CalibrationError"]


class CalibrationError(ImageError):
    """No fitting master for a frame, or a master that cannot be used."""


class Calibration(ImageProcessor):
    """Bias-subtracts, dark-subtracts (scaled by exposure time) and flat-fields an image.

    Masters (written by ``nightcrew reduce`` or :func:`~nightcrew.images.calibration.build_master`)
    are the FITS files in ``masters`` whose ``IMAGETYP`` is ``master_bias``, ``master_dark`` or
    ``master_flat``; each frame gets the best fitting one of each kind (same binning, same filter
    for flats, closest exposure time for darks, closest night). The directory is indexed on first
    use (:meth:`reset` forgets the index) and loaded masters are kept in a bounded cache.

    Args:
        masters: VFS directory holding the masters.
        max_cached: Masters kept in memory.
        require_dark: Fail instead of skipping the dark when none fits.
        require_flat: Fail instead of skipping the flat when none fits.
    """

    def __init__(
        self,
        *,
        masters: str,
        max_cached: int = 8,
        require_dark: bool = False,
        require_flat: bool = False,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        require(bool(masters), "masters", "masters must name a VFS directory")
        require(max_cached >= 1, "max_cached", f"max_cached must be >= 1, got {max_cached}")
        self.masters = masters.rstrip("/")
        self.require_dark = require_dark
        self.require_flat = require_flat
        self._cache: CalibrationCache[Image] = CalibrationCache(max_cached)
        self._index: list[MasterInfo] | None = None

    async def __call__(self, image: Image) -> Image:
        key = frame_key(image.header)
        bias = await self._master(MasterKind.BIAS, key, required=True)
        assert bias is not None
        dark = await self._master(MasterKind.DARK, key, required=self.require_dark)
        flat = await self._master(MasterKind.FLAT, key, required=self.require_flat)
        try:
            return await asyncio.to_thread(calibrate_image, image, bias=bias, dark=dark, flat=flat)
        except ImageError as exc:
            raise CalibrationError(f"cannot calibrate with the masters in {self.masters}: {exc}") from exc

    async def reset(self) -> None:
        self._index = None
        self._cache.clear()

    async def _master(self, kind: MasterKind, key: FrameKey, *, required: bool) -> Image | None:
        cache_key = (kind, key.for_kind(kind))
        cached = self._cache.get(cache_key)
        if cached is not None:
            return cached
        info = select_master(await self._masters_index(), kind, key)
        if info is None:
            if required:
                raise CalibrationError(
                    f"no master {kind.value} in {self.masters} for binning {key.binning}"
                    + (f", filter {key.filter}" if kind is MasterKind.FLAT else "")
                )
            return None
        image = await Image.from_vfs(self.vfs, info.path)
        self._cache.put(cache_key, image)
        return image

    async def _masters_index(self) -> list[MasterInfo]:
        if self._index is None:
            index: list[MasterInfo] = []
            for name in sorted(await self.vfs.listdir(self.masters)):
                if not name.lower().endswith((".fits", ".fits.gz", ".fit")):
                    continue
                path = f"{self.masters}/{name}"
                try:
                    image = await Image.from_vfs(self.vfs, path)
                except ImageFormatError:
                    continue  # not every file in the directory must be a master
                kind = master_kind(image)
                if kind is not None:
                    index.append(MasterInfo(path, kind, frame_key(image.header)))
            self._index = index
        return self._index
