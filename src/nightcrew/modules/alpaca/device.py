"""What every Alpaca module shares: the server connection, calls that notice a lost device, reconnect.

:class:`AlpacaModule` goes first in an Alpaca module's bases (``class AlpacaFocuser(AlpacaModule,
BaseFocuser)``). It adds the YAML keys ``server``, ``device_number``, ``timeout``,
``connect_timeout``, ``poll_interval`` and ``reconnect_interval`` and gives the driver
:meth:`AlpacaModule._get`, :meth:`AlpacaModule._put` and :meth:`AlpacaModule._poll_until`.

Connection lifecycle: ``open()`` connects (and calls :meth:`AlpacaModule._on_connected`, where a
driver reads what the device can do). A module whose device cannot be reached - at start-up, or
later because a call failed with a connection error, a timeout or NotConnected, or because the
watch loop found the device disconnected - goes to ERROR state naming the device and the reason.
The watch loop then reconnects every ``reconnect_interval`` seconds and puts the module back to
READY by itself. Errors set for other reasons are left for ``reset_error()``.

The device runs in wall time, whatever the module's clock: polling and reconnecting use wall
seconds (a fast simulated clock must not hammer a real device).
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable, Iterator, Mapping
from typing import Any, ClassVar

from nightcrew.bridges.alpaca import AlpacaClient, AlpacaDevice, check_server_url
from nightcrew.bridges.alpaca.errors import AlpacaConnectionError, AlpacaNotConnectedError
from nightcrew.errors import ConfigError, NightcrewError, RemoteTimeoutError
from nightcrew.interfaces import ModuleState
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.module import Module

__all__ = ["LOST_DEVICE_ERRORS", "AlpacaModule"]

log = logging.getLogger(__name__)

#: Errors meaning the device is gone (not that it refused one call).
LOST_DEVICE_ERRORS = _LOST = (AlpacaConnectionError, AlpacaNotConnectedError, RemoteTimeoutError)


class AlpacaModule(Module):
    """The Alpaca side of a device module; put it before the device base class.

    Args:
        server: Base URL of the Alpaca server, ``http://HOST:PORT``.
        device_number: The device's number on that server.
        timeout: Wall seconds one HTTP call may take.
        connect_timeout: Wall seconds connecting may take.
        poll_interval: Wall seconds between polls of a running action (slew, exposure, move).
        reconnect_interval: Wall seconds between checks of the connection (and reconnects).
        **kwargs: Options of the device base class.
    """

    #: The Alpaca device type in the URL ("telescope", "camera", ...).
    device_type: ClassVar[str]

    def __init__(
        self,
        *,
        server: str,
        device_number: int = 0,
        timeout: float = 10.0,
        connect_timeout: float = 30.0,
        poll_interval: Period = 0.1,
        reconnect_interval: Period = 2.0,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        for key, value in (
            ("timeout", timeout),
            ("connect_timeout", connect_timeout),
            ("poll_interval", poll_interval),
            ("reconnect_interval", reconnect_interval),
        ):
            if not value > 0:
                raise ConfigError(f"must be > 0 seconds, got {value}", key=key)
        if not isinstance(device_number, int) or device_number < 0:
            raise ConfigError(f"must be an integer >= 0, got {device_number!r}", key="device_number")
        try:
            self._client = AlpacaClient(server, timeout=timeout)
        except ValueError as exc:
            raise ConfigError(str(exc), key="server") from None
        self.device: AlpacaDevice = self._client.device(self.device_type, device_number)
        self._connect_timeout = float(connect_timeout)
        self._poll_interval = float(poll_interval)
        self._reconnect_interval = float(reconnect_interval)
        self._lost: str | None = None

    @staticmethod
    def config_value_problems(values: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
        """What ``nightcrew check`` reports beyond types: a server that is no Alpaca base URL."""
        server = values.get("server")
        if isinstance(server, str):
            try:
                check_server_url(server)
            except ValueError as exc:
                yield "server", str(exc)

    # --- lifecycle -----------------------------------------------------------------------------

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        await self._client.open()
        try:
            await self._connect()
        except NightcrewError as exc:
            self._lost = str(exc)
        self.add_background_task(self._connection_loop, name="alpaca connection")
        await super().open()
        if self._lost is not None:
            self.set_error(f"cannot reach {self.device.name}: {self._lost}")

    async def close(self) -> None:
        try:
            await super().close()
        finally:
            await self._client.close()

    async def _connect(self) -> None:
        await self.device.connect(self._connect_timeout, self._poll_interval)
        await self._on_connected()
        log.info("%s: connected to %s", self.name, self.device.name)

    async def _on_connected(self) -> None:
        """Hook: read what the device is and can do (called after every (re)connect)."""

    def _connection_lost(self, reason: str) -> None:
        """Go to ERROR state; the connection loop reconnects and returns to READY."""
        if self._lost is None:
            log.warning("%s: lost %s: %s", self.name, self.device.name, reason)
        self._lost = reason
        self.set_error(f"lost {self.device.name}: {reason}")

    async def _connection_loop(self) -> None:
        while True:
            await asyncio.sleep(self._reconnect_interval)
            if self._lost is not None:
                await self._try_reconnect()
            elif self.state is ModuleState.READY:
                try:
                    connected = await self.device.get("connected")
                except _LOST as exc:
                    self._connection_lost(str(exc))
                    continue
                if connected is not True:
                    self._connection_lost("the device reports it is not connected")

    async def _try_reconnect(self) -> None:
        try:
            await self._connect()
        except NightcrewError as exc:
            log.debug("%s: still cannot reach %s: %s", self.name, self.device.name, exc)
            return
        self._lost = None
        if self.state is ModuleState.ERROR:
            await self.reset_error()
        log.info("%s: %s is back", self.name, self.device.name)

    # --- calls ---------------------------------------------------------------------------------

    async def _get(self, member: str, **params: Any) -> Any:
        """``GET member``; a lost device puts the module into ERROR state (and raises)."""
        try:
            return await self.device.get(member, **params)
        except _LOST as exc:
            self._connection_lost(str(exc))
            raise

    async def _put(self, member: str, **params: Any) -> Any:
        """``PUT member`` with form parameters; a lost device puts the module into ERROR state."""
        try:
            return await self.device.put(member, **params)
        except _LOST as exc:
            self._connection_lost(str(exc))
            raise

    async def _put_best_effort(self, member: str) -> None:
        """``PUT member`` (AbortSlew, Halt, ...) while a motion is being cancelled: a failure is logged,
        not raised, so that the cancellation goes on."""
        try:
            await self.device.put(member)
        except Exception as exc:
            log.warning("%s: %s on %s failed: %s", self.name, member, self.device.name, exc)

    async def _poll_until(
        self,
        member: str,
        done: Callable[[Any], bool],
        time_limit: float,
        what: str,
        error: type[NightcrewError],
    ) -> Any:
        """Poll ``GET member`` until ``done(value)``; ``error`` naming ``what`` after ``time_limit`` s."""
        try:
            async with asyncio.timeout(time_limit):
                while True:
                    value = await self._get(member)
                    if done(value):
                        return value
                    await asyncio.sleep(self._poll_interval)
        except TimeoutError:
            raise error(f"{self.device.name}: {what} did not finish within {time_limit:g} s") from None
