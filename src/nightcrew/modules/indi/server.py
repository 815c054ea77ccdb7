"""IndiServer: nightcrew's devices offered to INDI clients (KStars/Ekos, Stellarium, indi_getprop).

The module listens for INDI clients (protocol 1.7 over TCP, 127.0.0.1:7624 by default) and
serves the nightcrew modules it is given by name - a telescope, camera, focuser, filter wheel
and dome - each as an INDI device of the same name with the standard property names. It reaches
them through proxies like any module, so they may run in this process or elsewhere over XMPP.

Properties follow the devices: every ``poll_interval`` wall seconds, and at once when a device
sends a motion, exposure or filter event, the server reads each device and sends what changed.
A client's request becomes a nightcrew call (see the tables in :mod:`.server_telescope` and, in
``modules/served``, ``camera_indi``, ``focuser_indi``, ``filterwheel_indi`` and ``dome_indi``);
its property is Busy while the call runs, Ok when it returns, Alert with the error as message when
it fails. A request nightcrew cannot take (unknown property, number out of range, read-only property,
malformed XML) is answered with Alert or a message, or - for broken XML - by closing that
client's connection; the server and its other clients carry on.

Why not indipyserver (PyPI, the server companion of indipydriver): its client reader does not
stop at end of stream, so every client that disconnects - indi_getprop does after each query -
leaves a task spinning at full CPU until a write to it fails (measured: 2.99 s CPU in 3 s). Its
driver package alone talks only over stdin/stdout. The protocol side kept here is small
(:mod:`nightcrew.bridges.indi.server_vectors`, :mod:`nightcrew.bridges.indi.server_listener`).
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import logging
import xml.etree.ElementTree as ET
from typing import Any

from nightcrew.bridges.indi.server_listener import IndiClient, IndiListener
from nightcrew.bridges.indi.server_vectors import (
    Property,
    PropertyState,
    blob_message,
    def_element,
    message_element,
    parse_new,
    set_element,
)
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.events import ExposureStatusChangedEvent, FilterChangedEvent, MotionStatusChangedEvent
from nightcrew.events.base import Event
from nightcrew.interfaces import ModuleState
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.indi.server_manual import ManualMode
from nightcrew.modules.indi.server_telescope import ServedTelescope
from nightcrew.modules.module import Module
from nightcrew.modules.served.camera_indi import ServedCamera
from nightcrew.modules.served.device_indi import ServedDevice
from nightcrew.modules.served.dome_indi import ServedDome
from nightcrew.modules.served.filterwheel_indi import ServedFilterWheel
from nightcrew.modules.served.focuser_indi import ServedFocuser

__all__ = ["IndiServer"]

log = logging.getLogger(__name__)

#: Wall seconds between two attempts to reach a module that is not online yet, at most.
_MAX_ATTACH_DELAY = 30.0


class IndiServer(Module):
    """Serves nightcrew devices to INDI clients.

    Args:
        host: Address to listen on; loopback by default. Other machines reach it only when this
            is an outside address (or ``0.0.0.0``), so think of who may then slew the telescope.
        port: TCP port (INDI's usual 7624; 0 picks a free one).
        telescope: Name of an ITelescope module to serve.
        camera: Name of an ICamera module; its images are read through this module's ``vfs``,
            which needs the camera's root (e.g. ``images``).
        focuser: Name of an IFocuser module.
        filters: Name of an IFilters module.
        dome: Name of an IRoof or IDome module.
        poll_interval: Wall seconds between two reads of each device (clients see in wall time,
            also when the observatory runs on a fast simulated clock).
        max_clients: Most INDI clients connected at once.
        max_clients_per_address: Most INDI clients connected at once from one address.
        idle_timeout: Wall seconds a client may take to send its first complete element (every
            INDI client starts with ``getProperties``) and to finish each element it begins; then
            it is disconnected. A client that spoke may listen in silence.
        pixel_size: The camera's pixel size in µm for CCD_INFO until a frame's XPIXSZ says (0:
            unknown until then).
        robotic: Name of the robotic module (IStartStop, the mastermind) that INDI clients take
            the observatory from: see :mod:`.server_manual` for the rule.
        handover_timeout: Wall seconds the robotic module gets to end its task and park.
        **kwargs: Module options (``site`` gives the telescope's GEOGRAPHIC_COORD).
    """

    def __init__(
        self,
        *,
        host: str = "127.0.0.1",
        port: int = 7624,
        telescope: str | None = None,
        camera: str | None = None,
        focuser: str | None = None,
        filters: str | None = None,
        dome: str | None = None,
        poll_interval: Period = 1.0,
        max_clients: int = 16,
        max_clients_per_address: int = 4,
        idle_timeout: float = 30.0,
        pixel_size: float = 0.0,
        robotic: str | None = None,
        handover_timeout: float = 300.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not isinstance(port, int) or not 0 <= port <= 65535:
            raise ConfigError(f"must be a TCP port 0..65535, got {port!r}", key="port")
        if not poll_interval > 0:
            raise ConfigError(f"must be > 0 seconds, got {poll_interval}", key="poll_interval")
        if not max_clients >= 1:
            raise ConfigError(f"must be >= 1, got {max_clients}", key="max_clients")
        if not max_clients_per_address >= 1:
            raise ConfigError(f"must be >= 1, got {max_clients_per_address}", key="max_clients_per_address")
        if not 0.1 <= idle_timeout <= 86400:
            raise ConfigError(f"must be 0.1 .. 86400 seconds, got {idle_timeout}", key="idle_timeout")
        if not (isinstance(pixel_size, (int, float)) and 0.0 <= pixel_size <= 100.0):
            raise ConfigError(f"must be 0 .. 100 µm, got {pixel_size!r}", key="pixel_size")
        if not 1.0 <= handover_timeout <= 3600.0:
            raise ConfigError(f"must be 1 .. 3600 seconds, got {handover_timeout}", key="handover_timeout")
        self._pixel_size = float(pixel_size)
        kinds: dict[str, tuple[str | None, type[ServedDevice[Any]]]] = {
            "telescope": (telescope, ServedTelescope),
            "camera": (camera, ServedCamera),
            "focuser": (focuser, ServedFocuser),
            "filters": (filters, ServedFilterWheel),
            "dome": (dome, ServedDome),
        }
        self._devices: dict[str, ServedDevice[Any]] = {}
        for key, (module, cls) in kinds.items():
            if module is None:
                continue
            if not isinstance(module, str) or not module.strip():
                raise ConfigError(f"must be a module name, got {module!r}", key=key)
            if module in self._devices:
                raise ConfigError(f"module {module!r} is already served as another device", key=key)
            self._devices[module] = cls(module, self)
        if not self._devices:
            raise ConfigError(
                "nothing to serve: give telescope, camera, focuser, filters or dome", key="telescope"
            )
        self._poll_interval = float(poll_interval)
        self._wakes = {name: asyncio.Event() for name in self._devices}
        self._attached: set[str] = set()
        self._listener = IndiListener(
            host,
            port,
            self._on_element,
            max_clients=max_clients,
            max_clients_per_address=max_clients_per_address,
            idle_timeout=float(idle_timeout),
        )
        self._manual: ManualMode | None = None
        if robotic is not None:
            if not isinstance(robotic, str) or not robotic.strip():
                raise ConfigError(f"must be a module name, got {robotic!r}", key="robotic")
            parked = [module for key, (module, _) in kinds.items() if module and key in ("telescope", "dome")]
            self._manual = ManualMode(robotic, self.proxy, parked, float(handover_timeout), self._announce)
        for name in self._devices:
            self.add_background_task(functools.partial(self._serve_device, name), name=f"INDI device {name}")

    @property
    def port(self) -> int:
        """The port clients connect to (the chosen one when configured as 0)."""
        return self._listener.port

    @property
    def pixel_size(self) -> float:
        return self._pixel_size

    @property
    def devices(self) -> dict[str, ServedDevice[Any]]:
        """The served devices by INDI device name (= nightcrew module name)."""
        return dict(self._devices)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await self._listener.start()
        try:
            await super().open()
            for event_type in (MotionStatusChangedEvent, ExposureStatusChangedEvent, FilterChangedEvent):
                await self.comm.register_event(event_type, self._on_device_event)
        except BaseException:
            await self._listener.close()
            raise

    async def close(self) -> None:
        if self.state in (ModuleState.CLOSING, ModuleState.CLOSED):
            return
        try:
            await super().close()
        finally:
            for device in self._devices.values():
                await device.close()
            await self._listener.close()

    # --- ServerLink ----------------------------------------------------------------------------

    def publish(self, vector: Property[Any]) -> None:
        if vector.device in self._attached:
            self._listener.broadcast(_xml(set_element(vector)), vector.device, vector.name)

    def publish_blob(self, vector: Property[Any], member: str, data: bytes, fmt: str) -> None:
        if self._listener.wanted(vector.device, vector.name, is_blob=True):  # encode only for someone
            message = blob_message(vector, member, data, fmt)
            self._listener.broadcast(message, vector.device, vector.name, is_blob=True)

    def _announce(self, text: str) -> None:
        self._listener.broadcast(_xml(message_element(None, text)), None, None)

    def wake(self, device: str) -> None:
        if device in self._wakes:
            self._wakes[device].set()

    # --- devices -------------------------------------------------------------------------------

    async def _serve_device(self, name: str) -> None:
        device = self._devices[name]
        await self._attach(device)
        self._attached.add(name)
        for vector in device.vectors.values():
            self._listener.broadcast(_xml(def_element(vector)), name, vector.name)
        wake = self._wakes[name]
        while True:
            await device.refresh()
            with contextlib.suppress(TimeoutError):
                async with asyncio.timeout(self._poll_interval):
                    await wake.wait()
            wake.clear()

    async def _attach(self, device: ServedDevice[Any]) -> None:
        delay = 1.0
        while True:
            try:
                await device.attach(await self.proxy(device.name, device.interface))
                log.info("serving %s over INDI as %s", device.name, type(device).__name__)
                return
            except NightcrewError as exc:
                log.warning("cannot serve %s over INDI yet (retrying in %g s): %s", device.name, delay, exc)
            await asyncio.sleep(delay)
            delay = min(2.0 * delay, _MAX_ATTACH_DELAY)

    async def _on_device_event(self, event: Event, sender: str) -> None:
        self.wake(sender)

    # --- clients -------------------------------------------------------------------------------

    async def _on_element(self, client: IndiClient, element: ET.Element) -> None:
        tag = element.tag
        if tag == "getProperties" or tag.startswith("new"):  # what clients ask for (bench/ekos.py)
            log.debug(
                "INDI client %s: %s %s.%s", client.address, tag, element.get("device"), element.get("name")
            )
        if tag == "getProperties":
            self._define(client, element.get("device"), element.get("name"))
        elif tag.startswith("new") and tag.endswith("Vector"):
            await self._on_request(client, element)
        else:
            log.debug("INDI client %s sent <%s>, which a server does not take", client.address, tag)

    def _define(self, client: IndiClient, device: str | None, name: str | None) -> None:
        for served in self._devices.values():
            if served.name not in self._attached or device not in (None, served.name):
                continue
            for vector in served.vectors.values():
                if name in (None, vector.name):
                    client.send(_xml(def_element(vector)))

    async def _on_request(self, client: IndiClient, element: ET.Element) -> None:
        device_name, name = element.get("device"), element.get("name")
        served = self._devices.get(device_name or "")
        vector = served.vectors.get(name or "") if served is not None else None
        if served is None or vector is None:
            text = f"no property {device_name}.{name} here"
            log.info("INDI client %s: %s", client.address, text)
            client.send(_xml(message_element(device_name if served is not None else None, text)))
            return
        try:
            values = parse_new(element, vector)
            if self._manual is not None:
                await self._manual.take(client.address)
            await served.request(vector, values)
        except NightcrewError as exc:
            log.info("INDI client %s: %s refused: %s", client.address, vector.where, exc)
            vector.state, vector.message = PropertyState.ALERT, str(exc)
            self.publish(vector)
        except Exception as exc:  # a bug of ours: Alert with the reason, never the client's connection
            log.exception("INDI client %s: %s failed", client.address, vector.where)
            vector.state, vector.message = PropertyState.ALERT, f"{type(exc).__name__}: {exc}"
            self.publish(vector)


def _xml(element: ET.Element) -> bytes:
    return ET.tostring(element) + b"\n"
