"""An asyncio INDI client: one TCP connection to an indiserver, kept up, with the properties it knows.

Why our own and not indipyclient (PyPI): indipyclient logs and skips malformed XML and carries on,
does not check BLOB sizes, retries every 5 s in busy-wait loops and decodes BLOBs on the event
loop's own stack without limits; nightcrew needs one clear error naming device and property, the
waiters failed at once when the server goes, and quick reconnects. The XML itself is parsed by
expat (:mod:`nightcrew.bridges.indi.stream`); this file only moves bytes and keeps state.

Waiting is driven by property state: :meth:`IndiClient.send` writes a ``new*Vector`` and (by
default) waits until the server has answered it and the vector is no longer Busy; Alert raises
:class:`IndiAlertError`. Every wait is bounded by a timeout in wall seconds (INDI devices move in
real time, whatever nightcrew's clock does).

Connection loss (server killed, malformed stream): every waiter gets :class:`IndiConnectionError`
(or the :class:`IndiProtocolError` that broke the stream), the known properties are dropped and
the client reconnects by itself with a growing delay until :meth:`close`.
"""

from __future__ import annotations

import asyncio
import contextlib
import dataclasses
import logging
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from nightcrew.bridges.indi.protocol import (
    DefVector,
    DelProperty,
    IndiError,
    IndiMessage,
    IndiProtocolError,
    PropertyState,
    ServerMessage,
    SetVector,
    Vector,
    VectorKind,
    enable_blob,
    get_properties,
    new_vector,
)
from nightcrew.bridges.indi.stream import IndiStreamParser

__all__ = [
    "IndiAlertError",
    "IndiClient",
    "IndiConnectionError",
    "IndiTimeoutError",
    "IndiUpdate",
]

log = logging.getLogger(__name__)

_READ_SIZE = 1 << 20
_FIRST_RETRY = 0.1
_MAX_RETRY = 5.0
_CONNECT_TIMEOUT = 10.0


class IndiConnectionError(IndiError):
    """No connection to the indiserver (refused, lost, or closed)."""


class IndiAlertError(IndiError):
    """A property went to Alert after we changed it."""


class IndiTimeoutError(IndiError):
    """A property did not reach the awaited state in time."""


@dataclass(frozen=True)
class IndiUpdate:
    """What a listener is told: a vector defined, changed or deleted, a message, or the connection.

    ``vector`` is a snapshot of the vector as this update left it (None for messages and
    connection changes); ``deleted`` is set for delProperty.
    """

    device: str
    name: str
    vector: Vector | None
    message: str = ""
    deleted: bool = False
    connected: bool = True


Listener = Callable[[IndiUpdate], None]


class IndiClient:
    """A client of one indiserver.

    Args:
        host: Server address.
        port: Server port (7624 is INDI's).
        devices: Only ask for these devices' properties; all when None.
        blobs: Devices whose BLOBs we want (``enableBLOB Also``); others send none.
    """

    def __init__(
        self,
        host: str,
        port: int = 7624,
        *,
        devices: Iterable[str] | None = None,
        blobs: Iterable[str] = (),
    ) -> None:
        if not host:
            raise ValueError("the indiserver's host must not be empty")
        if not 0 < port < 65536:
            raise ValueError(f"port must be within 1..65535, got {port}")
        self.host, self.port = host, port
        self._devices = sorted(set(devices)) if devices is not None else None
        self._blobs = sorted(set(blobs))
        self.properties: dict[tuple[str, str], Vector] = {}
        self.messages: dict[str, str] = {}  # device → its last message
        self._listeners: list[Listener] = []
        self._waiters: dict[tuple[str, str], set[asyncio.Future[None]]] = {}
        self._writer: asyncio.StreamWriter | None = None
        self._task: asyncio.Task[None] | None = None
        self._connected = asyncio.Event()
        self.last_error = "not connected yet"
        self.connections = 0

    @property
    def address(self) -> str:
        return f"{self.host}:{self.port}"

    @property
    def connected(self) -> bool:
        return self._writer is not None

    # --- life cycle ----------------------------------------------------------------------------

    async def open(self) -> None:
        """Start connecting (returns at once; see :meth:`wait_connected`)."""
        if self._task is None:
            self._task = asyncio.get_running_loop().create_task(
                self._connection_loop(), name=f"indi {self.address}"
            )

    async def close(self) -> None:
        """Disconnect and stop reconnecting; safe to call twice."""
        task, self._task = self._task, None
        if task is not None:
            task.cancel()
            await asyncio.gather(task, return_exceptions=True)
        self._drop(IndiConnectionError(f"client of {self.address} closed"))

    async def wait_connected(self, within: float) -> None:
        """Wait until connected, at most ``within`` wall seconds."""
        try:
            async with asyncio.timeout(within):
                await self._connected.wait()
        except TimeoutError:
            raise IndiConnectionError(
                f"no connection to indiserver {self.address} within {within:g} s: {self.last_error}"
            ) from None

    def add_listener(self, listener: Listener) -> None:
        """Call ``listener`` (synchronously, so keep it short) on every update."""
        self._listeners.append(listener)

    def remove_listener(self, listener: Listener) -> None:
        with contextlib.suppress(ValueError):
            self._listeners.remove(listener)

    # --- the connection ------------------------------------------------------------------------

    async def _connection_loop(self) -> None:
        delay = _FIRST_RETRY
        while True:
            try:
                reader, writer = await asyncio.wait_for(
                    asyncio.open_connection(self.host, self.port, limit=_READ_SIZE), _CONNECT_TIMEOUT
                )
            except (OSError, TimeoutError) as exc:
                self.last_error = f"cannot connect to indiserver {self.address}: {exc or type(exc).__name__}"
                await asyncio.sleep(delay)
                delay = min(delay * 2, _MAX_RETRY)
                continue
            delay = _FIRST_RETRY
            error = await self._session(reader, writer)
            self._drop(error)
            log.warning("%s", error)
            await asyncio.sleep(delay)

    async def _session(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> IndiError:
        """Talk to the server until the connection breaks; return why it broke."""
        parser = IndiStreamParser()
        self._writer = writer
        self.connections += 1
        try:
            for device in self._devices if self._devices is not None else [None]:
                writer.write(get_properties(device))
            for device in self._blobs:
                writer.write(enable_blob(device, "Also"))
            await writer.drain()
            self._connected.set()
            self.last_error = ""
            self._notify(IndiUpdate("", "", None, connected=True))
            while True:
                data = await reader.read(_READ_SIZE)
                if not data:
                    parser.close()
                    return IndiConnectionError(f"indiserver {self.address} closed the connection")
                for message in parser.feed(data):
                    self._apply(message)
        except IndiError as exc:
            return exc
        except OSError as exc:
            return IndiConnectionError(f"connection to indiserver {self.address} lost: {exc}")
        finally:
            self._writer = None
            writer.close()
            with contextlib.suppress(OSError):
                await writer.wait_closed()

    def _drop(self, error: IndiError) -> None:
        """Forget everything the lost connection told us; fail every waiter with ``error``."""
        was_connected = self._connected.is_set()
        self._connected.clear()
        self.last_error = str(error)
        self.properties.clear()
        waiters, self._waiters = self._waiters, {}
        for futures in waiters.values():
            for future in futures:
                if not future.done():
                    future.set_exception(error)
        if was_connected:
            self._notify(IndiUpdate("", "", None, message=str(error), connected=False))

    # --- incoming ------------------------------------------------------------------------------

    def _apply(self, message: ServerMessage) -> None:
        if isinstance(message, SetVector):
            vector = self.properties.get((message.device, message.name))
            if vector is None:
                return  # set before def (e.g. after a delProperty): nothing to update
            if vector.kind is not message.kind:
                raise IndiProtocolError(
                    f"set{message.kind.value}Vector for a {vector.kind.value} vector",
                    device=message.device,
                    name=message.name,
                )
            vector.members.update(message.members)
            if message.state is not None:
                vector.state = message.state
            if message.timeout is not None:
                vector.timeout = message.timeout
            vector.message = message.message
            if message.message:
                self.messages[message.device] = message.message
            vector.generation += 1
            if vector.state is PropertyState.BUSY:
                vector.busy_generation = vector.generation
            self._changed(vector)
        elif isinstance(message, DefVector):
            vector = message.vector
            old = self.properties.get(vector.key)
            vector.generation = old.generation + 1 if old is not None else 1
            self.properties[vector.key] = vector
            if vector.kind is VectorKind.BLOB and vector.device in self._blobs and self._writer is not None:
                self._writer.write(enable_blob(vector.device, "Also", vector.name))
            self._changed(vector)
        elif isinstance(message, DelProperty):
            self._delete(message)
        elif isinstance(message, IndiMessage):
            if message.message:
                self.messages[message.device] = message.message
            self._notify(IndiUpdate(message.device, "", None, message=message.message))

    def _changed(self, vector: Vector) -> None:
        self._wake(vector.key)
        if self._listeners:  # a snapshot: listeners may look later, when the vector has moved on
            snapshot = dataclasses.replace(vector, members=dict(vector.members))
            self._notify(IndiUpdate(vector.device, vector.name, snapshot, message=vector.message))

    def _delete(self, message: DelProperty) -> None:
        keys = [
            key
            for key in self.properties
            if key[0] == message.device and (not message.name or key[1] == message.name)
        ]
        for key in keys:
            vector = self.properties.pop(key)
            self._wake(key)
            self._notify(IndiUpdate(key[0], key[1], vector, message=message.message, deleted=True))

    def _wake(self, key: tuple[str, str]) -> None:
        for future in self._waiters.pop(key, ()):
            if not future.done():
                future.set_result(None)

    def _notify(self, update: IndiUpdate) -> None:
        for listener in list(self._listeners):
            try:
                listener(update)
            except Exception:
                log.exception("INDI listener failed on %s.%s", update.device, update.name)

    # --- waiting -------------------------------------------------------------------------------

    def vector(self, device: str, name: str) -> Vector:
        """The vector as last reported; raises IndiError if the server has not defined it."""
        if not self.connected:
            raise IndiConnectionError(self.last_error, device=device, name=name)
        vector = self.properties.get((device, name))
        if vector is None:
            raise IndiError("not defined by the server (yet)", device=device, name=name)
        return vector

    async def wait(
        self,
        device: str,
        name: str,
        condition: Callable[[Vector], bool],
        within: float,
        what: str = "the awaited state",
    ) -> Vector:
        """Wait until the vector exists and ``condition(vector)`` holds.

        Raises:
            IndiTimeoutError: Not within ``within`` wall seconds.
            IndiConnectionError / IndiProtocolError: The connection broke meanwhile.
        """
        key = (device, name)
        try:
            async with asyncio.timeout(within):
                while True:
                    if not self.connected:
                        await self._connected.wait()
                        continue
                    vector = self.properties.get(key)
                    if vector is not None and condition(vector):
                        return vector
                    future = asyncio.get_running_loop().create_future()
                    self._waiters.setdefault(key, set()).add(future)
                    await future
        except IndiError as exc:
            if exc.device:
                raise
            # The connection broke: say what we were waiting for.
            raise type(exc)(f"waiting for {what}: {exc}", device=device, name=name) from exc
        except TimeoutError:
            state = self.properties.get(key)
            now = f"it is {state.state.value}" if state is not None else "it is not defined"
            raise IndiTimeoutError(
                f"did not reach {what} within {within:g} s ({now}; {self.last_error or 'connected'})",
                device=device,
                name=name,
            ) from None

    async def wait_defined(self, device: str, name: str, within: float) -> Vector:
        return await self.wait(device, name, lambda v: True, within, "being defined")

    async def send(
        self,
        device: str,
        name: str,
        members: dict[str, float | bool | str],
        *,
        wait: float = 0.0,
        done: Callable[[Vector], bool] | None = None,
    ) -> Vector:
        """Send ``new*Vector``; with ``wait`` > 0 (wall seconds), wait for the answer and the end of Busy.

        Done when the server has updated the vector since our request and it is not Busy. With
        ``done``, an update that was not preceded by Busy must also satisfy ``done(vector)``: a
        periodic Ok the driver sent before it read our request must not end the wait. Alert
        raises IndiAlertError with the device's message.
        """
        vector = self.vector(device, name)
        unknown = set(members) - set(vector.members)
        if unknown:
            raise IndiError(f"has no member {', '.join(sorted(unknown))}", device=device, name=name)
        writer = self._writer
        if writer is None:
            raise IndiConnectionError(self.last_error, device=device, name=name)
        sent = vector.generation
        writer.write(new_vector(device, name, vector.kind, members))
        await writer.drain()
        if wait <= 0:
            return vector

        def finished(v: Vector) -> bool:
            if v.generation <= sent or v.state is PropertyState.BUSY:
                return False
            went_busy = v.busy_generation > sent
            return v.state is PropertyState.ALERT or done is None or went_busy or done(v)

        result = await self.wait(device, name, finished, wait, "the end of the request")
        if result.state is PropertyState.ALERT:
            detail = result.message or self.messages.get(device, "") or "no message"
            raise IndiAlertError(f"went to Alert: {detail}", device=device, name=name)
        return result
