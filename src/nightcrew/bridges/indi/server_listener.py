"""The TCP side of an INDI server: clients, their XML streams, their BLOB wishes, their queues.

:class:`IndiListener` accepts INDI clients (KStars/Ekos, Stellarium, ``indi_getprop``) on one
address and hands every complete top-level element a client sends to a handler, one at a time
per client. ``enableBLOB`` is kept per client here (BLOBs go only to those that asked, as the
protocol says). What a client sends is never trusted: malformed XML, an element larger than
``max_element_bytes``, or a client that does not read what it is sent (more than
``max_pending_bytes`` queued) closes that client's connection with a log line, and nothing else.

Nobody locks the others out: one address holds at most ``max_clients_per_address`` connections,
and a connection that says nothing - no complete element within ``idle_timeout`` wall seconds of
connecting, or an element begun and not finished within it - is dropped. A client that spoke
(every INDI client starts with ``getProperties``) may then listen in silence as long as it likes.
When a new connection finds its address, or the server, full, the oldest connection of that
address (or any) that never spoke makes room; if every one spoke, the new one is refused.

Each connection is an :class:`asyncio.Protocol` rather than a stream pair on purpose: a client
such as ``indi_setprop`` sends its request and hangs up without reading the rest of the property
definitions; the next write then fails, and a StreamReader would drop the request it had
already received. Here every byte received is handled, whatever happens to the writing side.
"""

from __future__ import annotations

import asyncio
import logging
import os
import socket
import xml.etree.ElementTree as ET
from collections import deque
from collections.abc import Awaitable, Callable, Iterator
from typing import cast

from nightcrew.errors import ModuleError

__all__ = ["IndiClient", "IndiListener"]

log = logging.getLogger(__name__)

_READ_CHUNK = 65536
#: Received chunks held before reading from the socket pauses (and when it resumes).
_PAUSE_CHUNKS, _RESUME_CHUNKS = 64, 8


class IndiClient(asyncio.Protocol):
    """One connected client: what it sent, its BLOB policy and what waits to be sent to it."""

    def __init__(self, max_pending_bytes: int, on_connected: Callable[[IndiClient], None]) -> None:
        self.address = "?"
        self.host = "?"  # the address without the port: what the per-address limit counts
        #: Whether the client completed an element: a silent connection can be dropped for it.
        self.spoke = False
        self._on_connected = on_connected
        self._transport: asyncio.Transport | None = None
        self._received: asyncio.Queue[bytes] = asyncio.Queue()  # b"" marks the end of the stream
        self._reading_paused = False
        self._max_pending = max_pending_bytes
        self._outgoing: deque[bytes] = deque()
        self._pending = 0
        self._wake = asyncio.Event()
        self._writable = asyncio.Event()
        self._writable.set()
        self._closed = False
        # (device, property or None) -> Never / Also / Only; Never by default, as the protocol says.
        self._blob_policy: dict[tuple[str, str | None], str] = {}

    # --- asyncio.Protocol ----------------------------------------------------------------------

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self._transport = transport
        peer = transport.get_extra_info("peername")
        self.address = f"{peer[0]}:{peer[1]}" if isinstance(peer, tuple) else str(peer)
        self.host = str(peer[0]) if isinstance(peer, tuple) else str(peer)
        self._on_connected(self)

    def data_received(self, data: bytes) -> None:
        self._received.put_nowait(data)
        if self._received.qsize() > _PAUSE_CHUNKS and self._transport is not None:
            self._transport.pause_reading()
            self._reading_paused = True

    def eof_received(self) -> bool:
        self._received.put_nowait(b"")
        return False

    def connection_lost(self, exc: Exception | None) -> None:
        if exc is not None:
            self._read_what_is_left()
        self._received.put_nowait(b"")
        self._closed = True
        self._wake.set()
        self._writable.set()

    def _read_what_is_left(self) -> None:
        """Take what the kernel still holds from the client before the transport closes the socket.

        A client that hangs up right after its request (indi_setprop does) makes our next write
        fail; the transport then closes the socket without reading the request that arrived.
        """
        socket_info = self._transport.get_extra_info("socket") if self._transport is not None else None
        if socket_info is None:
            return
        try:
            with socket.socket(fileno=os.dup(socket_info.fileno())) as sock:
                while data := sock.recv(_READ_CHUNK, socket.MSG_DONTWAIT):
                    self._received.put_nowait(data)
        except OSError:
            pass  # nothing more to read (BlockingIOError) or the connection is gone

    def pause_writing(self) -> None:
        self._writable.clear()

    def resume_writing(self) -> None:
        self._writable.set()

    # --- for the listener and the server -------------------------------------------------------

    @property
    def closed(self) -> bool:
        return self._closed

    async def receive(self) -> bytes:
        """The next chunk the client sent; b"" once it hung up."""
        chunk = await self._received.get()
        if self._reading_paused and self._received.qsize() < _RESUME_CHUNKS and self._transport is not None:
            self._transport.resume_reading()
            self._reading_paused = False
        return chunk

    def set_blob_policy(self, element: ET.Element) -> None:
        """Apply an ``enableBLOB``; an invalid one is logged and ignored."""
        device, name, policy = element.get("device"), element.get("name"), (element.text or "").strip()
        if not device or policy not in ("Never", "Also", "Only"):
            log.warning(
                "INDI client %s sent an invalid enableBLOB (device=%r, %r)", self.address, device, policy
            )
            return
        self._blob_policy[(device, name)] = policy

    def wants(self, device: str | None, name: str | None, is_blob: bool) -> bool:
        """Whether this client gets a message of ``device``'s property ``name``."""
        if device is None:
            return not is_blob
        policy = self._blob_policy.get((device, name)) or self._blob_policy.get((device, None), "Never")
        return policy != "Never" if is_blob else policy != "Only"

    def send(self, data: bytes) -> None:
        """Queue ``data``; a client that lets too much pile up is disconnected."""
        if self._closed:
            return
        if self._pending + len(data) > self._max_pending and self._outgoing:
            log.warning("INDI client %s does not read what it is sent; disconnecting it", self.address)
            self.close()
            return
        self._outgoing.append(data)
        self._pending += len(data)
        self._wake.set()

    def close(self) -> None:
        if not self._closed:
            self._closed = True
            self._outgoing.clear()
            self._wake.set()
            if self._transport is not None:
                self._transport.close()

    async def write_loop(self) -> None:
        """Write the queue out until the client is closed, as fast as it reads."""
        while not self._closed:
            await self._wake.wait()
            self._wake.clear()
            while self._outgoing and not self._closed:
                await self._writable.wait()
                # A failed send closes the transport before connection_lost runs: write no more
                # (asyncio warns "socket.send() raised exception." for each write after it).
                if self._closed or self._transport is None or self._transport.is_closing():
                    return
                data = self._outgoing.popleft()
                self._pending -= len(data)
                self._transport.write(data)


ElementHandler = Callable[[IndiClient, ET.Element], Awaitable[None]]


class IndiListener:
    """Serves INDI clients on ``host:port`` (port 0: a free port, see :attr:`port`).

    Args:
        handler: Called with every complete top-level element a client sends except
            ``enableBLOB``; awaited before the client's next element is read.
        max_clients: Connections beyond this are closed at once (unless a silent one makes room).
        max_clients_per_address: The same for the connections of one address.
        idle_timeout: Wall seconds a client may take to send its first complete element, and
            to finish each element it begins; then it is disconnected.
        max_element_bytes: Largest element a client may send (the server accepts no BLOBs).
        max_pending_bytes: Most a client may leave unread before it is disconnected.
    """

    def __init__(
        self,
        host: str,
        port: int,
        handler: ElementHandler,
        *,
        max_clients: int = 16,
        max_clients_per_address: int = 4,
        idle_timeout: float = 30.0,
        max_element_bytes: int = 1 << 20,
        max_pending_bytes: int = 256 << 20,
    ) -> None:
        self._host, self._port = host, port
        self._handler = handler
        self._max_clients = max_clients
        self._max_per_address = max_clients_per_address
        self._idle_timeout = idle_timeout
        self._max_element = max_element_bytes
        self._max_pending = max_pending_bytes
        self._server: asyncio.Server | None = None
        self._clients: dict[IndiClient, asyncio.Task[None]] = {}

    @property
    def port(self) -> int:
        """The port listened on (the chosen one when started with port 0)."""
        if self._server is None or not self._server.sockets:
            return self._port
        return int(self._server.sockets[0].getsockname()[1])

    @property
    def clients(self) -> list[IndiClient]:
        return [c for c in self._clients if not c.closed]

    async def start(self) -> None:
        loop = asyncio.get_running_loop()
        try:
            self._server = await loop.create_server(self._new_client, self._host, self._port)
        except OSError as exc:
            raise ModuleError(f"cannot listen for INDI clients on {self._host}:{self._port}: {exc}") from exc
        log.info("INDI server listening on %s:%d", self._host, self.port)

    async def close(self) -> None:
        """Stop listening and disconnect every client; safe to call twice."""
        if self._server is not None:
            self._server.close()
        for client in list(self._clients):
            client.close()
        tasks = list(self._clients.values())
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        if self._server is not None:
            await self._server.wait_closed()
            self._server = None

    def wanted(self, device: str | None, name: str | None, *, is_blob: bool = False) -> bool:
        """Whether any client wants messages of ``device``'s property ``name`` (a BLOB: enabled it)."""
        return any(client.wants(device, name, is_blob) for client in self.clients)

    def broadcast(self, data: bytes, device: str | None, name: str | None, *, is_blob: bool = False) -> None:
        """Queue ``data`` for every client that wants it."""
        for client in self.clients:
            if client.wants(device, name, is_blob):
                client.send(data)

    def _new_client(self) -> IndiClient:
        return IndiClient(self._max_pending, self._connected)

    def _connected(self, client: IndiClient) -> None:
        task = asyncio.get_running_loop().create_task(
            self._serve(client), name=f"INDI client {client.address}"
        )
        self._clients[client] = task

    async def _serve(self, client: IndiClient) -> None:
        refusal = self._make_room(client)
        if refusal is not None:
            log.warning("INDI client %s refused: %s", client.address, refusal)
            client.close()
            self._clients.pop(client, None)
            return
        log.info("INDI client %s connected", client.address)
        writing = asyncio.create_task(client.write_loop(), name=f"INDI writer {client.address}")
        try:
            await self._read_loop(client)
        finally:
            client.close()
            writing.cancel()
            await asyncio.gather(writing, return_exceptions=True)
            self._clients.pop(client, None)
            log.info("INDI client %s disconnected", client.address)

    def _make_room(self, new: IndiClient) -> str | None:
        """Room for ``new`` within the limits (dropping silent connections), or why there is none."""
        others = [c for c in self.clients if c is not new]
        for limit, group, what in (
            (self._max_per_address, [c for c in others if c.host == new.host], f"from {new.host}"),
            (self._max_clients, others, "in all"),
        ):
            if len(group) < limit:
                continue
            silent = next((c for c in group if not c.spoke), None)  # oldest first (insertion order)
            if silent is None:
                return f"already {limit} clients {what}"
            log.warning("INDI client %s dropped: it never spoke, and a new one needs room", silent.address)
            silent.close()
            others.remove(silent)
        return None

    async def _receive(self, client: IndiClient, deadline: float | None) -> bytes | None:
        """The client's next chunk; None when ``deadline`` (loop time) passes first."""
        if deadline is None:
            return await client.receive()
        try:
            async with asyncio.timeout_at(deadline):
                return await client.receive()
        except TimeoutError:
            return None

    async def _read_loop(self, client: IndiClient) -> None:
        # INDI is a stream of top-level elements without a document around them: feed them into one.
        parser: ET.XMLPullParser[ET.Element] = ET.XMLPullParser(events=("start", "end"))
        parser.feed(b"<indi>")
        depth, document, unfinished, in_tag = 0, None, 0, False
        loop = asyncio.get_running_loop()
        # Until the first complete element, and while one is unfinished, the client must go on.
        deadline: float | None = loop.time() + self._idle_timeout
        while True:
            chunk = await self._receive(client, deadline)
            if chunk is None:
                log.warning(
                    "INDI client %s sent no complete element within %g s; disconnecting it",
                    client.address,
                    self._idle_timeout,
                )
                return
            if not chunk:
                return  # the client hung up (an unfinished element is dropped with it)
            unfinished += len(chunk)
            try:
                parser.feed(chunk)
                # Only start and end events were asked for: each carries an element.
                events = list(cast(Iterator[tuple[str, ET.Element]], parser.read_events()))
            except ET.ParseError as exc:
                log.warning("INDI client %s sent malformed XML (%s); disconnecting it", client.address, exc)
                return
            for event, element in events:
                if event == "start":
                    depth += 1
                    if document is None:
                        document = element
                    continue
                depth -= 1
                if depth != 1:
                    continue
                unfinished, client.spoke = 0, True
                if document is not None:
                    document.remove(element)  # keep memory flat over a long session
                if element.tag == "enableBLOB":
                    client.set_blob_policy(element)
                    continue
                try:
                    await self._handler(client, element)
                except Exception:  # a bug answering one client must not end the others' service
                    log.exception("INDI client %s: handling <%s> failed", client.address, element.tag)
            if unfinished > self._max_element:
                log.warning(
                    "INDI client %s sent an element over %d bytes; disconnecting it",
                    client.address,
                    self._max_element,
                )
                return
            if chunk.strip():
                in_tag = not chunk.rstrip().endswith(b">")  # a tag begun, not finished
            if client.spoke and depth <= 1 and not in_tag:
                deadline = None  # between elements: a client may listen in silence
            elif deadline is None:
                deadline = loop.time() + self._idle_timeout  # an element begun must be finished
