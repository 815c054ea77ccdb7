"""A TCP proxy on 127.0.0.1 in front of a real indiserver that spoils the stream once, on request.

The INDI data is the real server's; the proxy only injects the fault a test names: malformed XML,
a stream cut off halfway through a BLOB, or a BLOB whose announced size is a lie.
"""

from __future__ import annotations

import asyncio
import contextlib
import re
from collections.abc import AsyncIterator

from nightcrew.testing.indi import IndiServer

_BLOB_TAG = re.compile(rb'(<oneBLOB[^>]*?size=")(\d+)(")')
_BLOB_START = b"<setBLOBVector"
_MALFORMED = (
    b'<setNumberVector device="Focuser Simulator" name="ABS_FOCUS_POSITION" state="Ok">'
    b"<oneNumber <</oneNumber>"
)


class FaultyProxy:
    """Forwards one indiserver; ``fault`` (``"malformed"``, ``"truncate_blob"``, ``"lying_blob"``)
    is applied to the next suitable data going to the client, then cleared."""

    def __init__(self, server: IndiServer) -> None:
        self._server = server
        self.fault = ""
        self.applied = asyncio.Event()
        self.port = 0
        self._listener: asyncio.Server | None = None
        self._tasks: set[asyncio.Task[None]] = set()

    async def __aenter__(self) -> FaultyProxy:
        self._listener = await asyncio.start_server(self._serve, "127.0.0.1", 0)
        self.port = self._listener.sockets[0].getsockname()[1]
        return self

    async def __aexit__(self, *exc: object) -> None:
        if self._listener is not None:
            self._listener.close()
        for task in list(self._tasks):
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)

    def spoil(self, fault: str) -> None:
        self.fault = fault
        self.applied.clear()

    async def _serve(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        task = asyncio.current_task()
        assert task is not None
        self._tasks.add(task)
        try:
            up_reader, up_writer = await asyncio.open_connection(self._server.host, self._server.port)
        except OSError:
            writer.close()
            self._tasks.discard(task)
            return
        upstream = asyncio.ensure_future(self._pump_up(reader, up_writer))
        try:
            async for chunk in self._spoiled(up_reader):
                writer.write(chunk)
                await writer.drain()
        except (OSError, _CutOff):
            pass
        finally:
            upstream.cancel()
            await asyncio.gather(upstream, return_exceptions=True)
            for w in (writer, up_writer):
                w.close()
            self._tasks.discard(task)

    async def _pump_up(self, reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        with contextlib.suppress(OSError):
            while data := await reader.read(65536):
                writer.write(data)
                await writer.drain()

    async def _spoiled(self, reader: asyncio.StreamReader) -> AsyncIterator[bytes]:
        held = b""
        while data := await reader.read(1 << 20):
            held += data
            fault = self.fault
            if fault == "malformed":
                cut = held.rfind(b"<set")
                if cut > 0:
                    yield held[:cut] + _MALFORMED
                    self._done()
                    held = held[cut:]
                continue
            if fault == "truncate_blob":
                start = held.find(_BLOB_START)
                if start >= 0 and len(held) > start + 20000:
                    yield held[: start + 20000]
                    self._done()
                    raise _CutOff
                if start >= 0:
                    continue  # hold back until enough of the BLOB is here to cut it in its middle
            if fault == "lying_blob":
                match = _BLOB_TAG.search(held)
                if match is not None:
                    held = held[: match.start(2)] + b"1000" + held[match.end(2) :]
                    self._done()
                elif _BLOB_START in held:
                    continue  # the tag is not complete yet
            yield held
            held = b""

    def _done(self) -> None:
        self.fault = ""
        self.applied.set()


class _CutOff(Exception):
    """The proxy ends the connection halfway through a message."""
