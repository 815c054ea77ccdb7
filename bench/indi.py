"""Benchmark of the INDI client side against the indi-bin simulators (needs root and indi-bin).

Run: ``.venv/bin/python bench/indi.py [--repeat 7] [--samples 20] [--size 1280x1024]``.

1. **BLOB download.** One exposure of the CCD simulator's full frame (``--size`` sets the
   simulator's chip; 1280x1024 is its default and largest preset) is recorded as it comes from
   indiserver: the property definitions, then the exposure's updates and the ``CCD1`` BLOB. A
   loopback server replays exactly these bytes, and in the same run we time (best of
   ``--repeat``):

   - *bare read*: ``asyncio`` reads the bytes and does nothing with them (the baseline);
   - *client*: :class:`~nightcrew.bridges.indi.IndiClient` parses the stream and decodes the BLOB
     (the time until its ``CCD1`` vector holds the image);
   - *module*: the same plus what IndiCamera does with the BLOB before the camera base writes
     nightcrew's file (:func:`~nightcrew.modules.indi.camera.fits_frame`: FITS to pixels).

   Goal: module ≥ 0.8 x the bare read's throughput.

2. **Event latency.** Another client (a thread with a blocking socket, timestamping bytes as they
   arrive) slews the simulated mount and aborts the slew, ``--samples`` times. Each change of the
   mount's ``EQUATORIAL_EOD_COORD`` state (to Busy, and back) makes IndiTelescope send a
   MotionStatusChangedEvent; the latency is the event's arrival at another module minus the
   arrival of the same update at the bare socket. Goal: median ≤ 5 ms.
"""

from __future__ import annotations

import argparse
import asyncio
import re
import socket
import statistics
import time
from collections.abc import Awaitable, Callable
from functools import partial
from typing import Any

from nightcrew.astro import j2000_to_of_date
from nightcrew.bridges.indi import IndiClient, Vector
from nightcrew.bridges.indi.protocol import Blob
from nightcrew.clock import RealClock
from nightcrew.events import MotionStatusChangedEvent
from nightcrew.interfaces import MotionStatus
from nightcrew.modules.indi import IndiTelescope
from nightcrew.modules.indi.camera import fits_frame
from nightcrew.testing import EventRecorder, Observatory, wait_for
from nightcrew.testing.indi import IndiServer

CCD = "CCD Simulator"
SCOPE = "Telescope Simulator"


# --- 1. BLOB download ----------------------------------------------------------------------------


def _send(sock: socket.socket, xml: str) -> None:
    sock.sendall(xml.encode())


def _read_until(sock: socket.socket, buffer: bytearray, marker: bytes, within: float) -> None:
    deadline = time.monotonic() + within
    while marker not in buffer:
        if time.monotonic() > deadline:
            raise TimeoutError(f"no {marker!r} within {within} s")
        sock.settimeout(max(0.01, deadline - time.monotonic()))
        chunk = sock.recv(1 << 20)
        if not chunk:
            raise ConnectionError("indiserver closed the connection")
        buffer += chunk


def record_exposure(server: IndiServer, width: int, height: int) -> bytes:
    """The bytes indiserver sends a client from getProperties through one full-frame BLOB."""
    with socket.create_connection((server.host, server.port), timeout=30) as sock:
        stream = bytearray()
        _send(sock, f'<getProperties version="1.7" device="{CCD}"/>')
        _read_until(sock, stream, b'name="CONNECTION"', 30)
        _send(
            sock,
            f'<newSwitchVector device="{CCD}" name="CONNECTION"><oneSwitch name="CONNECT">On</oneSwitch>'
            '<oneSwitch name="DISCONNECT">Off</oneSwitch></newSwitchVector>',
        )
        _read_until(sock, stream, b'defBLOBVector device="CCD Simulator" name="CCD1"', 30)
        _send(
            sock,
            f'<newNumberVector device="{CCD}" name="SIMULATOR_SETTINGS"><oneNumber name="SIM_XRES">{width}'
            f'</oneNumber><oneNumber name="SIM_YRES">{height}</oneNumber></newNumberVector>',
        )
        _send(sock, f'<enableBLOB device="{CCD}">Also</enableBLOB>')
        _send(
            sock,
            f'<newNumberVector device="{CCD}" name="CCD_FRAME"><oneNumber name="X">0</oneNumber>'
            f'<oneNumber name="Y">0</oneNumber><oneNumber name="WIDTH">{width}</oneNumber>'
            f'<oneNumber name="HEIGHT">{height}</oneNumber></newNumberVector>',
        )
        start = len(stream)
        _send(
            sock,
            f'<newNumberVector device="{CCD}" name="CCD_EXPOSURE">'
            '<oneNumber name="CCD_EXPOSURE_VALUE">0.01</oneNumber></newNumberVector>',
        )
        _read_until(sock, stream, b"</setBLOBVector>", 120)
        end = stream.index(b"</setBLOBVector>", start) + len(b"</setBLOBVector>")
        return bytes(stream[:end])


async def _replay_server(stream: bytes) -> asyncio.Server:
    async def serve(reader: asyncio.StreamReader, writer: asyncio.StreamWriter) -> None:
        writer.write(stream)
        await writer.drain()
        await reader.read()  # keep the connection until the client goes
        writer.close()

    return await asyncio.start_server(serve, "127.0.0.1", 0)


async def bare_read(port: int, size: int) -> float:
    start = time.perf_counter()
    reader, writer = await asyncio.open_connection("127.0.0.1", port, limit=1 << 20)
    received = 0
    while received < size:
        received += len(await reader.read(1 << 20))
    took = time.perf_counter() - start
    writer.close()
    return took


async def client_read(port: int, with_fits: bool) -> float:
    start = time.perf_counter()
    client = IndiClient("127.0.0.1", port, devices=[CCD])
    await client.open()
    vector = await client.wait(CCD, "CCD1", lambda v: v.generation > 1, 60, "the image")
    if with_fits:
        blob = vector.members["CCD1"]
        assert isinstance(blob, Blob)
        await fits_frame(blob, CCD)
    took = time.perf_counter() - start
    await client.close()
    return took


async def blob_table(
    server: IndiServer, width: int, height: int, repeat: int
) -> list[tuple[str, float, float]]:
    stream = record_exposure(server, width, height)
    replay = await _replay_server(stream)
    port = replay.sockets[0].getsockname()[1]
    try:
        best: dict[str, float] = {}
        for _ in range(repeat):  # interleaved, so that a busy moment hurts all alike
            runs: list[tuple[str, Callable[[], Awaitable[float]]]] = [
                ("bare read", partial(bare_read, port, len(stream))),
                ("client (parse + decode)", partial(client_read, port, False)),
                ("module (+ FITS to pixels)", partial(client_read, port, True)),
            ]
            for name, run in runs:
                took = await run()
                best[name] = min(best.get(name, float("inf")), took)
    finally:
        replay.close()
    mb = len(stream) / 1e6
    return [(name, took, mb / took) for name, took in best.items()]


# --- the same stream, live ------------------------------------------------------------------------


class WireTap(asyncio.Protocol):
    """A bare INDI client in the same event loop: keeps every chunk with its arrival time."""

    def __init__(self) -> None:
        self.chunks: list[tuple[float, bytes]] = []
        self.size = 0
        self.transport: asyncio.Transport | None = None
        self._state = ""
        self._tail = b""
        self.changes: list[tuple[float, str]] = []  # EQUATORIAL_EOD_COORD state changes
        self._pattern = re.compile(rb'name="EQUATORIAL_EOD_COORD"\s+state="(\w+)"')

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        assert isinstance(transport, asyncio.Transport)
        self.transport = transport

    def data_received(self, data: bytes) -> None:
        now = time.time()
        self.chunks.append((now, data))
        self.size += len(data)
        # A message may straddle two chunks: look at the end of the last one too.
        text = self._tail + data
        for match in self._pattern.finditer(text):
            if match.end() <= len(self._tail):
                continue  # seen with the last chunk
            state = match.group(1).decode()
            if state != self._state:
                self.changes.append((now, state))
                self._state = state
        self._tail = text[-200:]

    def send(self, xml: str) -> None:
        assert self.transport is not None
        self.transport.write(xml.encode())

    def arrival(self, marker: bytes, after: int) -> float | None:
        """When the chunk completing the first ``marker`` past byte ``after`` arrived."""
        stream, offset = b"", 0
        for when, chunk in self.chunks:
            offset += len(chunk)
            if offset <= after:
                continue
            stream += chunk
            if marker in stream[max(0, after - (offset - len(stream))) :]:
                return when
        return None


async def _tap(server: IndiServer, device: str, blobs: bool) -> WireTap:
    loop = asyncio.get_running_loop()
    _, tap = await loop.create_connection(WireTap, server.host, server.port)
    tap.send(f'<getProperties version="1.7" device="{device}"/>')
    if blobs:
        tap.send(f'<enableBLOB device="{device}">Also</enableBLOB>')
    return tap


def _newer(generation: int, vector: Vector) -> bool:
    blob = vector.members.get("CCD1")
    return vector.generation > generation and isinstance(blob, Blob) and bool(blob.data)


def _arrived(tap: WireTap, mark: int) -> bool:
    return tap.arrival(b"</setBLOBVector>", mark) is not None


async def live_blob_table(server: IndiServer, repeat: int) -> list[tuple[str, float]]:
    """Median download times of the CCD1 BLOB, from its first byte at the bare tap."""
    client = IndiClient(server.host, server.port, devices=[CCD], blobs=[CCD])
    await client.open()
    await client.wait_connected(within=10)
    await client.wait_defined(CCD, "CCD1", 30)
    tap = await _tap(server, CCD, blobs=True)
    times: dict[str, list[float]] = {
        "bare read": [],
        "client (parse + decode)": [],
        "module (+ FITS to pixels)": [],
    }
    try:
        for _ in range(repeat):
            generation, mark = client.vector(CCD, "CCD1").generation, tap.size
            await client.send(CCD, "CCD_EXPOSURE", {"CCD_EXPOSURE_VALUE": 0.01})
            vector = await client.wait(CCD, "CCD1", partial(_newer, generation), 60, "the image")
            parsed = time.time()
            blob = vector.members["CCD1"]
            assert isinstance(blob, Blob)
            await fits_frame(blob, CCD)
            converted = time.time()
            await wait_for(partial(_arrived, tap, mark), 30, message="the bare tap's copy")
            first = tap.arrival(b'<setBLOBVector device="CCD Simulator"', mark)
            done = tap.arrival(b"</setBLOBVector>", mark)
            assert first is not None and done is not None
            times["bare read"].append(done - first)
            times["client (parse + decode)"].append(parsed - first)
            times["module (+ FITS to pixels)"].append(converted - first)
    finally:
        await client.close()
        if tap.transport is not None:
            tap.transport.close()
    return [(name, statistics.median(values)) for name, values in times.items()]


# --- 2. event latency ----------------------------------------------------------------------------


async def latency_samples(server: IndiServer, samples: int) -> list[float]:
    tap = await _tap(server, SCOPE, blobs=False)
    # Commands go over a connection of their own: the tap only listens, like the module's client
    # (a connection that also sends stalls on TCP's delayed ACKs, ~40 ms, and would not compare).
    commander = await _tap(server, SCOPE, blobs=False)
    latencies: list[float] = []
    try:
        async with Observatory(clock=RealClock()) as obs:
            recorder = await obs.start(EventRecorder, "recorder", types=[MotionStatusChangedEvent])
            telescope = await obs.start(
                IndiTelescope, "telescope", host=server.host, port=server.port, device=SCOPE
            )
            await telescope.init()
            await telescope.move_altaz(45.0, 180.0)
            for i in range(samples):
                recorder.clear()
                tap.changes.clear()
                ra, dec = telescope._radec_of(45.0, 180.0 + (30.0 if i % 2 == 0 else -30.0))
                ra_now, dec_now = j2000_to_of_date(ra, dec, time.time())
                commander.send(
                    f'<newNumberVector device="{SCOPE}" name="EQUATORIAL_EOD_COORD"><oneNumber name="RA">'
                    f'{ra_now / 15}</oneNumber><oneNumber name="DEC">{dec_now}</oneNumber></newNumberVector>'
                )
                await wait_for(
                    lambda: telescope._motion_status is MotionStatus.SLEWING, 10, message="slewing"
                )
                commander.send(
                    f'<newSwitchVector device="{SCOPE}" name="TELESCOPE_ABORT_MOTION">'
                    '<oneSwitch name="ABORT">On</oneSwitch></newSwitchVector>'
                )
                await wait_for(
                    lambda: telescope._motion_status is not MotionStatus.SLEWING, 10, message="stopped"
                )
                await wait_for(lambda: len(tap.changes) >= 2, 10, message="the wire's changes")
                latencies += _pair(tap.changes, recorder)
    finally:
        for connection in (tap, commander):
            if connection.transport is not None:
                connection.transport.close()
    return latencies


def _pair(wire: list[tuple[float, str]], recorder: EventRecorder) -> list[float]:
    """Latencies of one cycle: wire Busy -> SLEWING event, wire end of Busy -> the next event."""
    events = [
        (t, e.status)
        for (e, _), t in zip(recorder.events, recorder.arrivals, strict=True)
        if isinstance(e, MotionStatusChangedEvent)
    ]
    busy_wire = next(t for t, state in wire if state == "Busy")
    end_wire = next(t for t, state in wire if t >= busy_wire and state != "Busy")
    slewing = next(t for t, status in events if status is MotionStatus.SLEWING)
    ended = next(t for t, status in events if t >= slewing and status is not MotionStatus.SLEWING)
    return [slewing - busy_wire, ended - end_wire]


def _parse_size(text: str) -> tuple[int, int]:
    width, _, height = text.partition("x")
    return int(width), int(height)


async def main(args: argparse.Namespace) -> None:
    width, height = args.size
    server = IndiServer(["indi_simulator_ccd", "indi_simulator_telescope"])
    server.start()
    try:
        rows = await blob_table(server, width, height, args.repeat)
        live = await live_blob_table(server, args.repeat)
        latencies = await latency_samples(server, args.samples)
    finally:
        server.stop()
    bare = rows[0][1]
    print(f"INDI BLOB download, {width}x{height} 16-bit frame replayed from loopback, best of {args.repeat}")
    print(f"{'path':28} {'time [ms]':>10} {'MB/s':>8} {'x bare':>7}")
    for name, took, rate in rows:
        print(f"{name:28} {took * 1e3:10.2f} {rate:8.1f} {bare / took:7.2f}")
    print()
    print(f"The same BLOB live from indiserver, from its first byte at a bare tap; median of {args.repeat}")
    print(f"{'path':28} {'time [ms]':>10} {'x bare':>7}")
    for name, took in live:
        print(f"{name:28} {took * 1e3:10.2f} {live[0][1] / took:7.2f}")
    print("goal: module >= 0.80 x bare")
    print()
    ms = sorted(1e3 * x for x in latencies)
    print(f"INDI property change -> nightcrew event ({len(ms)} state changes of the mount's coordinates)")
    print(f"{'median [ms]':>12} {'p90 [ms]':>9} {'min [ms]':>9} {'max [ms]':>9}")
    p90 = ms[min(len(ms) - 1, int(0.9 * len(ms)))]
    print(f"{statistics.median(ms):12.2f} {p90:9.2f} {ms[0]:9.2f} {ms[-1]:9.2f}")
    print("goal: median <= 5 ms")


def _arguments() -> Any:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0] if __doc__ else None)
    parser.add_argument("--repeat", type=int, default=7, help="download runs per path (best counts)")
    parser.add_argument("--samples", type=int, default=20, help="slew start/abort cycles")
    parser.add_argument("--size", type=_parse_size, default=(1280, 1024), help="chip WIDTHxHEIGHT")
    return parser.parse_args()


if __name__ == "__main__":
    asyncio.run(main(_arguments()))
