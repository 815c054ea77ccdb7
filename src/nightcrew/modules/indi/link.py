"""What every INDI device module shares: one device on one indiserver, kept connected.

A module owns an :class:`IndiLink` (composition, so it can sit on any device base). The link's
supervising task connects to the server, switches the device's ``CONNECTION`` on, waits for the
properties the module needs and lets the module read the device's state (``on_ready``). Then the
module is READY. When the server goes (killed, restarted, network) or the stream breaks, the module
goes to ERROR with the reason; when the device is back the link sets it up again and the module
returns to READY by itself.

YAML keys every INDI module takes: ``host``, ``port`` (7624), ``device`` (the INDI device name),
``connect_timeout`` (wall seconds to wait for server and device at start-up).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable, Iterable
from typing import Any, ClassVar

from nightcrew.bridges.indi import (
    IndiAlertError,
    IndiClient,
    IndiError,
    IndiUpdate,
    PropertyState,
    Vector,
)
from nightcrew.errors import ConfigError, ModuleError, NightcrewError
from nightcrew.interfaces import ModuleState
from nightcrew.modules.module import Module

__all__ = ["IndiLink", "IndiModule"]

log = logging.getLogger(__name__)

_RETRY_DELAY = 0.5


class IndiLink:
    """One INDI device of one module.

    Args:
        module: The module this link serves (its state follows the link).
        host: indiserver address.
        port: indiserver port.
        device: INDI device name, e.g. ``Telescope Simulator``.
        needs: Properties the module needs before it is ready.
        blobs: Whether the module wants the device's BLOBs.
        connect_timeout: Wall seconds to wait for server, device and properties.
    """

    def __init__(
        self,
        module: Module,
        *,
        host: str,
        port: int,
        device: str,
        needs: Iterable[str] = (),
        blobs: bool = False,
        connect_timeout: float = 10.0,
    ) -> None:
        if not host:
            raise ConfigError("name the indiserver's host", key="host")
        if not isinstance(port, int) or not 0 < port < 65536:
            raise ConfigError(f"must be a TCP port within 1..65535, got {port!r}", key="port")
        if not device:
            raise ConfigError("name the INDI device (as indiserver lists it)", key="device")
        if not connect_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {connect_timeout}", key="connect_timeout")
        self.module = module
        self.device = device
        self.connect_timeout = float(connect_timeout)
        self.client = IndiClient(host, port, devices=[device], blobs=[device] if blobs else [])
        self._needs = ["CONNECTION", *needs]
        self._on_ready: Callable[[], Awaitable[None]] | None = None
        self._ready = asyncio.Event()
        self._lost = asyncio.Event()
        self._reason = "not connected yet"
        self._set_error = False
        self._setting_up = False
        self.client.add_listener(self._watch)

    @property
    def ready(self) -> bool:
        return self._ready.is_set()

    @property
    def readable(self) -> bool:
        """Whether the device's vectors may be read: ready, or being set up (in ``on_ready``)."""
        return self.ready or self._setting_up

    @property
    def where(self) -> str:
        return f"INDI device '{self.device}' on {self.client.address}"

    def on_ready(self, callback: Callable[[], Awaitable[None]]) -> None:
        """Run ``callback`` after every (re)connection, before the module is ready again."""
        self._on_ready = callback

    async def open(self) -> None:
        """Start connecting (the module adds :meth:`supervise_loop` as a background task)."""
        await self.client.open()

    async def close(self) -> None:
        await self.client.close()

    async def wait_ready(self) -> None:
        """At start-up: wait ``connect_timeout`` for the device; put the module in ERROR if not."""
        try:
            async with asyncio.timeout(self.connect_timeout):
                await self._ready.wait()
        except TimeoutError:
            reason = self._reason if self.client.connected else self.client.last_error
            self._fail(f"{self.where} not ready within {self.connect_timeout:g} s: {reason}")

    # --- supervision ---------------------------------------------------------------------------

    async def supervise_loop(self) -> None:
        """Set the device up whenever the connection is (re)made; report losses. Runs until closed."""
        while True:
            try:
                await self.client.wait_connected(within=self.connect_timeout)
                self._setting_up = True
                await self._set_up()
            except (IndiError, NightcrewError) as exc:
                self._reason = str(exc)
                if self.module.state is ModuleState.READY and not self.ready:
                    self._fail(f"{self.where}: {exc}")
                await asyncio.sleep(_RETRY_DELAY)
                continue
            finally:
                self._setting_up = False
            self._lost.clear()
            self._ready.set()
            if self._set_error and self.module.state is ModuleState.ERROR:
                log.info("%s: %s is back", self.module.name, self.where)
                self._set_error = False
                await self.module.reset_error()
            await self._lost.wait()
            self._ready.clear()
            self._fail(f"{self.where} lost: {self._reason}")

    async def _set_up(self) -> None:
        connection = await self.client.wait_defined(self.device, "CONNECTION", self.connect_timeout)
        if not connection.members.get("CONNECT"):
            await self.client.send(
                self.device, "CONNECTION", {"CONNECT": True, "DISCONNECT": False}, wait=self.connect_timeout
            )
        for name in self._needs:
            await self.client.wait_defined(self.device, name, self.connect_timeout)
        if self._on_ready is not None:
            await self._on_ready()

    def _watch(self, update: IndiUpdate) -> None:
        if not self.ready:
            return
        if not update.connected:
            self._reason = update.message or "connection lost"
            self._lost.set()
        elif (
            update.device == self.device
            and update.deleted
            and (not update.name or update.name in self._needs)
        ):
            self._reason = f"the server deleted {update.name or 'the device'}"
            self._lost.set()
        elif (
            update.device == self.device
            and update.name == "CONNECTION"
            and update.vector is not None
            and not update.vector.members.get("CONNECT")
        ):
            self._reason = "the device was disconnected"
            self._lost.set()

    def _fail(self, message: str) -> None:
        if self.module.state is ModuleState.READY:
            self._set_error = True
            self.module.set_error(message)

    # --- access for the module -----------------------------------------------------------------

    def vector(self, name: str) -> Vector:
        """The device's vector ``name``; ModuleError while the device is not there."""
        if not self.readable:
            raise ModuleError(f"{self.where} is not ready: {self._reason}")
        try:
            return self.client.vector(self.device, name)
        except IndiError as exc:
            raise ModuleError(str(exc)) from exc

    def has(self, name: str) -> bool:
        return (self.device, name) in self.client.properties

    async def send(
        self,
        name: str,
        members: dict[str, float | bool | str],
        *,
        wait: float = 0.0,
        done: Callable[[Vector], bool] | None = None,
    ) -> Vector:
        """Change the device's vector ``name`` (see IndiClient.send); raises IndiError on failure."""
        return await self.client.send(self.device, name, members, wait=wait, done=done)

    async def switch(self, name: str, member: str, *, wait: float = 0.0) -> Vector:
        """Turn ``member`` of a OneOfMany switch vector On (the others Off)."""
        vector = self.client.vector(self.device, name)
        values: dict[str, float | bool | str] = {m: m == member for m in vector.members}
        if vector.rule == "AtMostOne" or vector.rule == "AnyOfMany":
            values = {member: True}
        return await self.send(name, values, wait=wait)

    async def abort(self, name: str) -> None:
        """Press the ABORT switch of vector ``name`` (if the device has it and is there).

        Drivers often answer an abort with Alert ("operation aborted"): that is the abort
        working, so it is logged, not raised.
        """
        if not self.ready or not self.has(name):
            return
        try:
            await self.send(name, {"ABORT": True}, wait=self.connect_timeout)
        except IndiAlertError as exc:
            log.info("%s: %s", self.module.name, exc)

    def is_busy(self, name: str) -> bool:
        vector = self.client.properties.get((self.device, name))
        return vector is not None and vector.state is PropertyState.BUSY


class IndiModule(Module):
    """The INDI side of a device module; put it before the device base class
    (``class IndiFocuser(IndiModule, BaseFocuser)``).

    Args:
        host: indiserver address.
        port: indiserver port.
        device: INDI device name.
        connect_timeout: Wall seconds to wait for server and device.
        move_timeout: Wall seconds one motion (slew, exposure readout, move) may take.
        **kwargs: Options of the device base class.
    """

    #: Properties the module needs before it is ready.
    indi_needs: ClassVar[tuple[str, ...]] = ()
    #: Whether the module wants the device's BLOBs.
    indi_blobs: ClassVar[bool] = False

    def __init__(
        self,
        *,
        host: str,
        port: int = 7624,
        device: str,
        connect_timeout: float = 10.0,
        move_timeout: float = 240.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        if not move_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {move_timeout}", key="move_timeout")
        self._move_timeout = float(move_timeout)
        self._indi = IndiLink(
            self,
            host=host,
            port=port,
            device=device,
            needs=self.indi_needs,
            blobs=self.indi_blobs,
            connect_timeout=connect_timeout,
        )
        self._indi.on_ready(self._on_indi_ready)
        self._indi_updates: asyncio.Queue[IndiUpdate] = asyncio.Queue()
        self._indi.client.add_listener(self._indi_updates.put_nowait)
        self.add_background_task(self._indi.supervise_loop)
        self.add_background_task(self._indi_update_loop)

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await self._indi.open()
        await super().open()
        await self._indi.wait_ready()

    async def close(self) -> None:
        await super().close()
        await self._indi.close()

    async def _on_indi_ready(self) -> None:
        """Read the device's state after every (re)connection (drivers override)."""

    async def _on_indi_update(self, update: IndiUpdate) -> None:
        """React to a change the device reported (drivers override; keep it quick)."""

    async def _indi_update_loop(self) -> None:
        while True:
            update = await self._indi_updates.get()
            if update.device == self._indi.device and update.vector is not None and self._indi.ready:
                await self._on_indi_update(update)
