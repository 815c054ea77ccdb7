"""Kiosk: the latest sky image as a PNG on a small web server, for a status screen or a web page.

Either it takes an image from ``camera`` (an IData module) every ``interval`` clock seconds, or,
without a camera, it shows the newest file announced by a NewImageEvent. The picture is served at
``http://HOST:PORT/kiosk.png`` (``/`` is a page showing it); 503 until there is one.
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

import numpy as np
import numpy.typing as npt
from aiohttp import web

from nightcrew.errors import ConfigError
from nightcrew.events import NewImageEvent
from nightcrew.images.png import encode_png, stretch_to_uint8
from nightcrew.interfaces import IData, IExposureTime, ModuleState
from nightcrew.interfaces.quantities import ExposureTime, Period
from nightcrew.modules.module import Module

__all__ = ["Kiosk"]

log = logging.getLogger(__name__)

_PAGE = """<!doctype html><html><head><meta http-equiv="refresh" content="{refresh}">
<title>{title}</title></head><body style="margin:0;background:#000">
<img src="kiosk.png" style="max-width:100%;max-height:100vh;display:block;margin:auto">
</body></html>"""


def _blocking_render(data: npt.NDArray[Any], max_size: int) -> bytes:
    return encode_png(stretch_to_uint8(data, max_size=max_size))


class Kiosk(Module):
    """Serves the latest image as a PNG over HTTP.

    Args:
        camera: An IData module to take images from; None: show images from NewImageEvents.
        interval: Clock seconds between two images taken from ``camera``.
        exposure_time: Exposure time set before each image (if the camera has IExposureTime).
        host: Address the web server listens on (127.0.0.1: this machine only).
        port: Its port; 0 picks a free one (see :attr:`port` after opening).
        max_size: Longest side of the PNG in pixels (the image is binned down to it).
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        camera: str | None = None,
        interval: Period = 60.0,
        exposure_time: ExposureTime | None = None,
        host: str = "127.0.0.1",
        port: int = 37080,
        max_size: int = 1024,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not interval > 0:
            raise ConfigError(f"must be > 0 seconds, got {interval}", key="interval")
        if not 0 <= port < 65536:
            raise ConfigError(f"must be a port number (0 picks a free one), got {port}", key="port")
        if not max_size >= 16:
            raise ConfigError(f"must be >= 16 pixels, got {max_size}", key="max_size")
        self._camera = camera
        self._interval = float(interval)
        self._exposure_time = exposure_time
        self._host, self._port, self._max_size = host, port, max_size
        self._png: bytes | None = None
        self._source = ""
        self._runner: web.AppRunner | None = None  # while open
        if camera is not None:
            self.add_background_task(self._grab_loop)

    @property
    def port(self) -> int:
        """The port the server listens on (the real one when configured as 0)."""
        return self._port

    @property
    def png(self) -> bytes | None:
        """The PNG being served, None before the first image."""
        return self._png

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await self._start_server()
        await super().open()
        if self._camera is None:
            await self.comm.register_event(NewImageEvent, self.on_new_image)

    async def close(self) -> None:
        await super().close()
        runner, self._runner = self._runner, None
        if runner is not None:
            await runner.cleanup()

    # --- images --------------------------------------------------------------------------------

    async def _grab_loop(self) -> None:
        assert self._camera is not None
        while True:
            try:
                camera = await self.proxy(self._camera, IData)
                if self._exposure_time is not None and isinstance(camera, IExposureTime):
                    await camera.set_exposure_time(self._exposure_time)
                await self.show(await camera.grab_data(broadcast=False))
            except Exception as exc:  # a camera off-line is no reason to stop showing the last image
                log.warning("%s: taking an image from %s failed: %s", self.name, self._camera, exc)
            await self.clock.sleep(self._interval)

    async def on_new_image(self, event: NewImageEvent, sender: str) -> None:
        await self.show(event.filename)

    async def show(self, path: str) -> None:
        """Render the FITS image at VFS ``path`` and serve it from now on."""
        hdul = await self.vfs.read_fits(path)
        data = next((hdu.data for hdu in hdul if hdu.data is not None and hdu.data.ndim >= 2), None)
        if data is None:
            log.warning("%s: %s holds no image", self.name, path)
            return
        self._png = await asyncio.to_thread(_blocking_render, np.asarray(data), self._max_size)
        self._source = path

    # --- web server ----------------------------------------------------------------------------

    async def _start_server(self) -> None:
        async def page(request: web.Request) -> web.Response:
            refresh = max(5, int(self._interval)) if self._camera else 30
            return web.Response(text=_PAGE.format(refresh=refresh, title=self.name), content_type="text/html")

        async def image(request: web.Request) -> web.Response:
            if self._png is None:
                return web.Response(status=503, text="no image yet")
            return web.Response(
                body=self._png,
                content_type="image/png",
                headers={"Cache-Control": "no-cache", "X-Source": self._source},
            )

        app = web.Application()
        app.router.add_get("/", page)
        app.router.add_get("/kiosk.png", image)
        runner = web.AppRunner(app, access_log=None)
        await runner.setup()
        site = web.TCPSite(runner, self._host, self._port)
        try:
            await site.start()
        except OSError:
            await runner.cleanup()
            raise
        self._runner = runner
        self._port = runner.addresses[0][1]
        log.info("%s: serving the kiosk image at http://%s:%d/kiosk.png", self.name, self._host, self._port)
