"""The served camera: what Alpaca and INDI clients ask of a nightcrew ICamera, written once.

Both protocols take an exposure the same way: the settings their client chose (binning, window in
unbinned pixels, exposure time) go to the module, ``grab_data()`` writes the frame through the
camera's VFS, and the server reads that very file back through its own VFS (which must reach the
camera's file roots) to hand it to the client. The optional interfaces (IWindow, IBinning,
IStoppableExposure) are looked up on the module's proxy; a setting the module cannot take is
refused with an error naming the module.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from nightcrew.errors import GrabImageError, InvalidArgumentError, NightcrewError, NotSupportedError
from nightcrew.interfaces import (
    Binning,
    IBinning,
    ICamera,
    IExposureTime,
    ImageType,
    IStoppableExposure,
    IWindow,
    Window,
)

if TYPE_CHECKING:
    from nightcrew.vfs import VirtualFileSystem

__all__ = ["MAX_EXPOSURE", "ServedCameraRole", "read_frame"]

#: The longest exposure a client may ask for, in seconds.
MAX_EXPOSURE = 3600.0


class ServedCameraRole:
    """The ICamera module behind a served camera.

    Args:
        camera: The module's proxy (its other interfaces are checked on it).
        module: The module's name, for errors.
    """

    def __init__(self, camera: ICamera, module: str) -> None:
        self.camera = camera
        self.module = module

    # --- what the chip offers ------------------------------------------------------------------

    @property
    def window(self) -> IWindow | None:
        return self.camera if isinstance(self.camera, IWindow) else None

    async def full_frame(self) -> Window:
        """The whole chip in unbinned pixels (refused for a module without IWindow)."""
        if self.window is None:
            raise NotSupportedError(f"module {self.module} does not tell its chip size (no IWindow)")
        return await self.window.get_full_frame()

    async def binnings(self) -> list[Binning]:
        """The binnings the module offers (1x1 only without IBinning)."""
        if not isinstance(self.camera, IBinning):
            return [Binning(1, 1)]
        return await self.camera.list_binnings()

    @property
    def stoppable(self) -> IStoppableExposure | None:
        """The module as IStoppableExposure if it can end an exposure early and keep it."""
        return self.camera if isinstance(self.camera, IStoppableExposure) else None

    # --- exposing ------------------------------------------------------------------------------

    async def set_binning(self, binning: Binning) -> None:
        if isinstance(self.camera, IBinning):
            await self.camera.set_binning(binning.x, binning.y)
        elif binning != Binning(1, 1):
            raise InvalidArgumentError(f"module {self.module} cannot bin")

    async def set_window(self, window: Window) -> None:
        """Read ``window`` (unbinned pixels) from now on; a module without IWindow reads its whole chip."""
        if self.window is not None:
            await self.window.set_window(window.left, window.top, window.width, window.height)

    async def set_exposure_time(self, seconds: float) -> None:
        if not isinstance(self.camera, IExposureTime):
            raise NotSupportedError(f"module {self.module} has no settable exposure time (IExposureTime)")
        await self.camera.set_exposure_time(seconds)

    async def grab(self, image_type: ImageType) -> str:
        """Take a frame with the settings given; its VFS path (announced in a NewImageEvent)."""
        return await self.camera.grab_data(broadcast=True, image_type=image_type)


async def read_frame(vfs: VirtualFileSystem, path: str) -> bytes:
    """The FITS file the camera wrote, read through the server's VFS (one clear error if it cannot)."""
    try:
        return await vfs.read_bytes(path)
    except (NightcrewError, OSError) as exc:
        raise GrabImageError(f"cannot read the frame {path} through the server's VFS: {exc}") from exc
