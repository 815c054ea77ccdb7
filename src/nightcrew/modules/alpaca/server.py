"""AlpacaServer: nightcrew modules served as ASCOM Alpaca devices, so any Alpaca client can drive them.

Example (see ``examples/alpaca/server.yaml``)::

    class: nightcrew.modules.alpaca.AlpacaServer
    port: 11111
    devices:
      telescope: telescope        # module names; a list serves several devices of one type
      camera: [camera, guider]    # camera 0 and camera 1
      dome: roof                  # any IRoof module (an IDome adds the azimuth)
      focuser: focuser
      filterwheel: filters
      safetymonitor: weather      # the weather module's good/bad verdict
      observingconditions: station  # a weather station's (or the weather module's) sensors
    vfs: ...                      # must reach the camera's file roots (ImageArray reads the frame)

The devices are reached through proxies on the module's comm, so the observatory may run in this
process or anywhere on the XMPP network. The server listens on 127.0.0.1 unless ``host`` says
otherwise (``0.0.0.0`` exposes the devices to the whole network, unauthenticated, as Alpaca is);
the discovery responder listens on ``discovery_host`` (the same by default), port
``discovery_port`` (32227, the Alpaca standard; None: no discovery).
"""

from __future__ import annotations

import logging
from typing import Any

from aiohttp import web

from nightcrew.bridges.alpaca.discovery import DISCOVERY_PORT, DiscoveryResponder
from nightcrew.bridges.alpaca.server_app import ServerDescription, build_app
from nightcrew.bridges.alpaca.server_device import ServedDevice
from nightcrew.bridges.alpaca.server_devices import (
    ServedObservingConditions,
    ServedSafetyMonitor,
)
from nightcrew.bridges.alpaca.server_more import ServedCoverCalibrator, ServedRotator, ServedSwitch
from nightcrew.bridges.alpaca.server_telescope import ServedTelescope
from nightcrew.errors import ConfigError
from nightcrew.interfaces import ModuleState
from nightcrew.modules.module import Module
from nightcrew.modules.served.camera_alpaca import ServedCamera
from nightcrew.modules.served.dome_alpaca import ServedDome
from nightcrew.modules.served.filterwheel_alpaca import ServedFilterWheel
from nightcrew.modules.served.focuser_alpaca import ServedFocuser

__all__ = ["SERVED_TYPES", "AlpacaServer"]

log = logging.getLogger(__name__)

#: Alpaca device type (as in the ``devices`` option and in URLs) → the class serving it.
SERVED_TYPES: dict[str, type[ServedDevice]] = {
    cls.device_type: cls
    for cls in (
        ServedTelescope,
        ServedCamera,
        ServedDome,
        ServedFocuser,
        ServedFilterWheel,
        ServedSafetyMonitor,
        ServedObservingConditions,
        ServedRotator,
        ServedSwitch,
        ServedCoverCalibrator,
    )
}


class AlpacaServer(Module):
    """Serves nightcrew modules under the Alpaca device API, management API and discovery.

    Args:
        devices: Alpaca device type → module name, or a list of names (device numbers 0, 1, ...).
            Types: telescope, camera, dome, focuser, filterwheel, safetymonitor,
            observingconditions, rotator, switch, covercalibrator.
        host: Address the HTTP server listens on.
        port: HTTP port (11111 is customary; 0 picks a free port, see :attr:`port`).
        discovery_host: Address of the discovery responder; ``host`` when None.
        discovery_port: UDP port of the discovery responder (0: a free one; None: no discovery).
        server_name: ServerName in the management API (also makes the devices' UniqueIDs).
        location: Location in the management API.
        focuser_step: Millimetres per Alpaca focuser step.
        focuser_max_step: Largest Alpaca focuser position.
        pixel_sizes: Camera module → pixel size in µm (PixelSizeX/Y; NotImplemented without).
        settle_time: Wall seconds an asynchronous operation (a slew, ...) may take to be refused
            before the request that started it returns; later failures are reported on the next
            poll (Slewing, ImageReady, ...).
        **kwargs: Module options (``vfs`` must reach the cameras' files; ``site`` for the
            telescope's site and sidereal time).
    """

    def __init__(
        self,
        *,
        devices: dict[str, str | list[str]],
        host: str = "127.0.0.1",
        port: int = 11111,
        discovery_host: str | None = None,
        discovery_port: int | None = DISCOVERY_PORT,
        server_name: str = "nightcrew",
        location: str = "",
        focuser_step: float = 0.001,
        focuser_max_step: int = 100_000,
        pixel_sizes: dict[str, float] | None = None,
        settle_time: float = 0.2,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        for key, value in (("port", port), ("discovery_port", discovery_port)):
            if value is not None and not 0 <= value <= 65535:
                raise ConfigError(f"must be a port number (0..65535), got {value}", key=key)
        if not settle_time >= 0:
            raise ConfigError(f"must be >= 0 seconds, got {settle_time}", key="settle_time")
        self._host, self._requested_port = host, port
        self._description = ServerDescription(server_name, location)
        self._devices = _served_devices(
            self,
            devices,
            settle_time=float(settle_time),
            focuser=(focuser_step, focuser_max_step),
            pixel_sizes=dict(pixel_sizes or {}),
        )
        self._runner: web.AppRunner | None = None
        self._port = 0
        self._discovery: DiscoveryResponder | None = None
        self._discovery_host = discovery_host or host
        self._discovery_port = discovery_port

    @property
    def port(self) -> int:
        """The HTTP port listened on (after :meth:`open`)."""
        return self._port

    @property
    def discovery_port(self) -> int | None:
        """The UDP port of the discovery responder (after :meth:`open`), None without one."""
        return self._discovery.port if self._discovery is not None else None

    @property
    def url(self) -> str:
        return f"http://{self._host}:{self._port}"

    @property
    def devices(self) -> list[ServedDevice]:
        return list(self._devices)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await super().open()
        try:
            await self._start_serving()
        except BaseException:
            await self.close()
            raise
        log.info("%s: serving %d Alpaca devices at %s", self.name, len(self._devices), self.url)

    async def _start_serving(self) -> None:
        runner = web.AppRunner(build_app(self._description, self._devices), access_log=None)
        await runner.setup()
        self._runner = runner
        site = web.TCPSite(runner, self._host, self._requested_port)
        try:
            await site.start()
        except OSError as exc:
            raise ConfigError(
                f"cannot listen on {self._host}:{self._requested_port}: {exc}", key="port"
            ) from exc
        self._port = int(runner.addresses[0][1])
        if self._discovery_port is not None:
            responder = DiscoveryResponder(self._port, host=self._discovery_host, port=self._discovery_port)
            try:
                await responder.open()
            except OSError as exc:
                raise ConfigError(
                    f"cannot listen on {self._discovery_host}:{self._discovery_port}: {exc}",
                    key="discovery_port",
                ) from exc
            self._discovery = responder

    async def close(self) -> None:
        if self.state in (ModuleState.CLOSING, ModuleState.CLOSED):
            return
        if self._discovery is not None:
            await self._discovery.close()
        runner, self._runner = self._runner, None
        for device in self._devices:
            await device.action.cancel()
        if runner is not None:
            await runner.cleanup()
        await super().close()


def _served_devices(
    owner: Module,
    devices: dict[str, str | list[str]],
    *,
    settle_time: float,
    focuser: tuple[float, int],
    pixel_sizes: dict[str, float],
) -> list[ServedDevice]:
    if not isinstance(devices, dict) or not devices:
        raise ConfigError(
            "name at least one device: {telescope: <module>, camera: <module>, ...}", key="devices"
        )
    served: list[ServedDevice] = []
    for device_type, names in devices.items():
        cls = SERVED_TYPES.get(str(device_type).lower())
        if cls is None:
            known = ", ".join(SERVED_TYPES)
            raise ConfigError(f"unknown Alpaca device type; known: {known}", key=f"devices.{device_type}")
        modules = [names] if isinstance(names, str) else names
        if not modules or not all(isinstance(m, str) and m for m in modules):
            raise ConfigError("give a module name or a list of module names", key=f"devices.{device_type}")
        for number, module in enumerate(modules):
            options: dict[str, Any] = {"settle_time": settle_time}
            if cls is ServedFocuser:
                options.update(step=focuser[0], max_step=focuser[1])
            elif cls is ServedCamera:
                options["pixel_size"] = pixel_sizes.get(module)
            served.append(cls(owner, module, number, **options))
    cameras = {d.module for d in served if isinstance(d, ServedCamera)}
    for module, size in pixel_sizes.items():
        if module not in cameras:
            raise ConfigError(f"{module} is not a served camera", key=f"pixel_sizes.{module}")
        if not size > 0:
            raise ConfigError(f"must be > 0 µm, got {size}", key=f"pixel_sizes.{module}")
    return served
