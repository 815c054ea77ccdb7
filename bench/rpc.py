"""XMPP RPC benchmark: nightcrew vs a bare slixmpp IQ echo (the floor) vs pyobs-core, one table.

Starts its own Prosody (``nightcrew.server``) in a temp dir on a free loopback port, with an
account for every participant. Every pair runs in two processes: the callee is this script (or
``bench/pyobs_probe.py``) re-run as a child, the caller is this process (for pyobs, another
child). Both sides use STARTTLS with the server's self-signed certificate, as modules do.

Measured per row: median and p99 latency of ``--calls`` sequential calls of ``add(1.0, 2.0)``
(after a warm-up), and calls/s with ``--concurrency`` calls in flight (median of ``--rounds``).
Also: time from spawning ``nightcrew run module.yaml`` (StandAlone with an XmppComm) to its
"is ready" log line, and the resident memory of that process after ~2 s idle.

    .venv/bin/python bench/rpc.py [--calls 1000] [--concurrency 50] [--rounds 5] [--starts 5]
                                  [--pyobs-venv /tmp/pyobs-venv]
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import shutil
import signal
import socket
import statistics
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from abc import abstractmethod
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from nightcrew.comm.xmpp import XmppComm
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module
from nightcrew.server import Account, init_server, start_server, stop_server

HERE = Path(__file__).resolve().parent
DOMAIN = "bench.test"
PASSWORD = "bench-secret"
ROOM = "bench"
NS_ECHO = "urn:nightcrew:bench:echo"
#: Every participant of every row gets its own account (no session takes over another's).
USERS = ["adder", "caller", "echo", "pinger", "pyadder", "pycaller", *(f"start{i}" for i in range(20))]
_CHILD_READY_TIMEOUT = 30.0


# --- measurements (this process is always the caller) -----------------------------------------


@dataclass
class RpcFigures:
    median_ms: float
    p99_ms: float
    calls_per_s: float
    #: CPU time per call in the throughput rounds, caller + callee + Prosody: on a busy machine
    #: the steadiest figure of the three (wall times include other processes' turns).
    cpu_us: float


def process_cpu_s(pid: int) -> float:
    """User + system CPU seconds used so far by process ``pid`` (Linux /proc)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


async def measure(
    call: Callable[[], Awaitable[Any]],
    calls: int,
    concurrency: int,
    rounds: int,
    cpu: Callable[[], float],
) -> RpcFigures:
    """Latency of sequential calls, then throughput with ``concurrency`` calls in flight.

    ``cpu()`` returns the CPU seconds used so far by every process taking part.
    """
    for _ in range(min(100, calls)):  # warm-up: caches, TLS buffers, the server's routes
        await call()
    latencies = []
    for _ in range(calls):
        start = time.perf_counter()
        await call()
        latencies.append(time.perf_counter() - start)
    per_worker = max(1, calls // concurrency)

    async def worker() -> None:
        for _ in range(per_worker):
            await call()

    rates = []
    cpu_before = cpu()
    for _ in range(rounds):
        start = time.perf_counter()
        await asyncio.gather(*(worker() for _ in range(concurrency)))
        rates.append(per_worker * concurrency / (time.perf_counter() - start))
    cpu_used = cpu() - cpu_before
    return RpcFigures(
        median_ms=statistics.median(latencies) * 1e3,
        p99_ms=statistics.quantiles(latencies, n=100)[98] * 1e3,
        calls_per_s=statistics.median(rates),
        cpu_us=cpu_used / (rounds * per_worker * concurrency) * 1e6,
    )


# --- the nightcrew pair ------------------------------------------------------------------------


class IBenchAdder(Interface):
    @abstractmethod
    async def add(self, a: float, b: float) -> float: ...


class BenchAdder(Module, IBenchAdder):
    async def add(self, a: float, b: float) -> float:
        return a + b


@dataclass(frozen=True)
class Server:
    address: str
    ca_file: str
    pid: int = 0  # Prosody's, for its CPU time (0 in children, which do not measure)

    def cpu_with(self, callee: int) -> Callable[[], float]:
        """CPU seconds so far of this process, the callee and the server."""
        return lambda: time.process_time() + process_cpu_s(callee) + process_cpu_s(self.pid)

    def comm(self, user: str) -> XmppComm:
        return XmppComm(f"{user}@{DOMAIN}", PASSWORD, server=self.address, room=ROOM, ca_file=self.ca_file)


async def bench_nightcrew(server: Server, options: argparse.Namespace) -> RpcFigures:
    async with child(_self_command("adder", server)) as callee:
        caller = Module(comm=server.comm("caller"))
        await caller.open()
        try:
            await _wait_for(lambda: "adder" in caller.comm.clients, "adder did not join the room")
            adder = await caller.comm.proxy("adder", IBenchAdder)
            return await measure(
                lambda: adder.add(1.0, 2.0),
                options.calls,
                options.concurrency,
                options.rounds,
                cpu=server.cpu_with(callee.pid),
            )
        finally:
            await caller.close()


async def serve_adder(server: Server) -> None:
    adder = BenchAdder(comm=server.comm("adder"))
    await adder.open()
    try:
        await _announce_ready_and_wait_for_eof()
    finally:
        await adder.close()


# --- the raw slixmpp pair: an IQ answered at once, no XML-RPC ---------------------------------


def _raw_client(user: str, server: Server) -> Any:
    import slixmpp

    client = slixmpp.ClientXMPP(f"{user}@{DOMAIN}/raw", PASSWORD)
    client.enable_direct_tls = False  # STARTTLS, like XmppComm
    client.ca_certs = Path(server.ca_file)
    return client


async def _raw_connect(client: Any, server: Server) -> None:
    started: asyncio.Future[None] = asyncio.get_running_loop().create_future()

    def on_session(_: Any) -> None:
        if not started.done():
            started.set_result(None)

    client.add_event_handler("session_start", on_session)
    host, port = server.address.rsplit(":", 1)
    client.connect(host, int(port))
    await asyncio.wait_for(started, 10)
    raw = client.transport.get_extra_info("socket")
    raw.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)  # as XmppComm does


async def bench_raw(server: Server, options: argparse.Namespace) -> RpcFigures:
    async with child(_self_command("echo", server)) as callee:
        client = _raw_client("pinger", server)
        await _raw_connect(client, server)
        try:
            target = f"echo@{DOMAIN}/raw"

            async def ping() -> None:
                iq = client.make_iq_get(ito=target)
                iq.xml.append(ET.Element(f"{{{NS_ECHO}}}echo"))
                await iq.send(timeout=10)

            return await measure(
                ping, options.calls, options.concurrency, options.rounds, cpu=server.cpu_with(callee.pid)
            )
        finally:
            await client.disconnect(wait=1.0)


async def serve_echo(server: Server) -> None:
    from slixmpp.xmlstream.handler import Callback
    from slixmpp.xmlstream.matcher import MatchXPath

    client = _raw_client("echo", server)

    def answer(iq: Any) -> None:
        if iq["type"] == "get":
            iq.reply(clear=False).send()

    client.register_handler(Callback("echo", MatchXPath(f"{{jabber:client}}iq/{{{NS_ECHO}}}echo"), answer))
    await _raw_connect(client, server)
    try:
        await _announce_ready_and_wait_for_eof()
    finally:
        await client.disconnect(wait=1.0)


# --- pyobs-core, in its own venv ----------------------------------------------------------------


async def bench_pyobs(server: Server, python: Path, options: argparse.Namespace) -> RpcFigures:
    await _befriend(server, "pyadder", "pycaller")
    probe = str(HERE / "pyobs_probe.py")
    common = ["--server", server.address, "--domain", DOMAIN, "--password", PASSWORD]
    async with child([str(python), probe, "serve", "--user", "pyadder", *common]) as callee:
        command = [str(python), probe, "call", "--user", "pycaller", "--callee", "pyadder", *common]
        command += ["--calls", str(options.calls), "--concurrency", str(options.concurrency)]
        command += ["--rounds", str(options.rounds)]
        process = await asyncio.create_subprocess_exec(
            *command, stdin=asyncio.subprocess.DEVNULL, stdout=asyncio.subprocess.PIPE
        )
        try:
            figures = await asyncio.wait_for(_probe_figures(process, server, callee.pid), 600)
        finally:
            await _end(process)
        if process.returncode != 0:
            raise RuntimeError(f"pyobs probe failed (exit {process.returncode})")
        return figures


async def _probe_figures(process: asyncio.subprocess.Process, server: Server, callee: int) -> RpcFigures:
    """Read the probe's output; at each ``mark <its CPU s>`` line add the callee's and server's CPU."""
    assert process.stdout is not None
    others = [0.0, 0.0]
    probe_cpu = [0.0, 0.0]
    marks = 0
    async for line in process.stdout:
        words = line.decode().split()
        if words[:1] == ["mark"] and marks < 2:
            probe_cpu[marks] = float(words[1])
            others[marks] = process_cpu_s(callee) + process_cpu_s(server.pid)
            marks += 1
        elif line.startswith(b"{"):
            data = json.loads(line)
            calls = data.pop("throughput_calls")
            cpu_used = probe_cpu[1] - probe_cpu[0] + others[1] - others[0]
            await process.wait()
            return RpcFigures(**data, cpu_us=cpu_used / calls * 1e6)
    await process.wait()
    raise RuntimeError(f"pyobs probe failed (exit {process.returncode})")


async def _befriend(server: Server, first: str, second: str) -> None:
    """Mutual roster subscriptions: pyobs finds its peers by roster presence, not by a room."""
    clients = [_raw_client(user, server) for user in (first, second)]
    for client in clients:
        client.auto_authorize = True
        client.auto_subscribe = True
        await _raw_connect(client, server)
        await client.get_roster()
        client.send_presence()  # subscription requests go to available resources
    try:
        clients[0].send_presence_subscription(pto=f"{second}@{DOMAIN}")
        clients[1].send_presence_subscription(pto=f"{first}@{DOMAIN}")

        def mutual() -> bool:
            return all(
                client.client_roster[f"{peer}@{DOMAIN}"]["subscription"] == "both"
                for client, peer in zip(clients, (second, first), strict=True)
            )

        await _wait_for(mutual, "pyobs accounts did not subscribe to each other")
    finally:
        for client in clients:
            await client.disconnect(wait=1.0)


# --- start-up time and idle memory of `nightcrew run` ------------------------------------------


@dataclass
class StartFigures:
    ready_s: list[float]
    rss_mb: float
    python_s: float


async def bench_start(server: Server, directory: Path, starts: int) -> StartFigures:
    ready_s = []
    rss_mb = 0.0
    for i in range(starts):
        config = directory / f"start{i}.yaml"
        config.write_text(
            "class: nightcrew.modules.test.StandAlone\n"
            "message: idle\n"
            "interval: 3600\n"
            "comm:\n"
            "  class: nightcrew.comm.xmpp.XmppComm\n"
            f"  jid: start{i}@{DOMAIN}\n"
            f"  password: {PASSWORD}\n"
            f"  server: {server.address}\n"
            f"  room: {ROOM}\n"
            f"  ca_file: {server.ca_file}\n"
        )
        start = time.perf_counter()
        process = await asyncio.create_subprocess_exec(
            sys.executable,
            "-m",
            "nightcrew",
            "run",
            str(config),
            stdin=asyncio.subprocess.DEVNULL,
            stdout=asyncio.subprocess.DEVNULL,
            stderr=asyncio.subprocess.PIPE,
        )
        try:
            await asyncio.wait_for(_read_until(process, b"is ready"), _CHILD_READY_TIMEOUT)
            ready_s.append(time.perf_counter() - start)
            if i == 0:  # memory once: every start is the same process
                await asyncio.sleep(2.0)
                rss_mb = _rss_mb(process.pid)
        finally:
            await _end(process)
    # The floor for any Python program on this machine: the interpreter alone.
    start = time.perf_counter()
    python = await asyncio.create_subprocess_exec(sys.executable, "-c", "pass")
    await python.wait()
    return StartFigures(ready_s, rss_mb, time.perf_counter() - start)


async def _read_until(process: asyncio.subprocess.Process, marker: bytes) -> None:
    assert process.stderr is not None
    seen: list[bytes] = []
    while True:
        line = await process.stderr.readline()
        if not line:
            raise RuntimeError("nightcrew run ended before READY:\n" + b"".join(seen).decode())
        seen.append(line)
        if marker in line:
            return


def _rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024  # kB
    return float("nan")


# --- children and the server --------------------------------------------------------------------


def _self_command(role: str, server: Server) -> list[str]:
    return [sys.executable, __file__, "--role", role, "--server", server.address, "--ca-file", server.ca_file]


@asynccontextmanager
async def child(command: list[str]) -> AsyncIterator[asyncio.subprocess.Process]:
    """A callee process; it prints ``ready`` once online and ends when its stdin closes."""
    process = await asyncio.create_subprocess_exec(
        *command, stdin=asyncio.subprocess.PIPE, stdout=asyncio.subprocess.PIPE
    )
    try:
        assert process.stdout is not None
        line = await asyncio.wait_for(process.stdout.readline(), _CHILD_READY_TIMEOUT)
        if line.strip() != b"ready":
            raise RuntimeError(f"{command[1]} did not start: {line!r}")
        yield process
    finally:
        await _end(process)


async def _end(process: asyncio.subprocess.Process) -> None:
    """Close stdin (the polite stop), then SIGTERM, then SIGKILL; never leaves a process behind."""
    if process.returncode is not None:
        return
    if process.stdin is not None:
        process.stdin.close()
    else:
        process.send_signal(signal.SIGTERM)
    try:
        await asyncio.wait_for(process.wait(), 5)
    except TimeoutError:
        process.kill()
        await process.wait()


async def _announce_ready_and_wait_for_eof() -> None:
    print("ready", flush=True)
    # A child ends when the parent closes stdin, or dies (EOF as well): no orphans.
    await asyncio.get_running_loop().run_in_executor(None, sys.stdin.buffer.read)


async def _wait_for(condition: Callable[[], bool], message: str, seconds: float = 20.0) -> None:
    deadline = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > deadline:
            raise RuntimeError(message)
        await asyncio.sleep(0.05)


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        port: int = sock.getsockname()[1]
        return port


# --- the table ----------------------------------------------------------------------------------


def _ratio(value: float, reference: float) -> str:
    return f"{value / reference:.2f}x"


def print_table(
    raw: RpcFigures, nightcrew: RpcFigures, pyobs: RpcFigures | None, pyobs_note: str, starts: StartFigures
) -> None:
    head = f"{'row (2 processes each, loopback)':<44} {'median ms':>9} {'p99 ms':>8} {'calls/s':>8}"
    print(head + f" {'CPU µs/call':>11} {'median vs raw':>13} {'calls/s vs raw':>14} {'CPU vs raw':>10}")
    rows = [("raw slixmpp IQ echo (floor), STARTTLS", raw), ("nightcrew RPC add(), STARTTLS", nightcrew)]
    if pyobs is not None:
        rows.append(("pyobs-core 2.19.1 RPC add(), no TLS", pyobs))
    for name, f in rows:
        print(
            f"{name:<44} {f.median_ms:>9.3f} {f.p99_ms:>8.3f} {f.calls_per_s:>8.0f} {f.cpu_us:>11.0f}"
            f" {_ratio(f.median_ms, raw.median_ms):>13} {_ratio(f.calls_per_s, raw.calls_per_s):>14}"
            f" {_ratio(f.cpu_us, raw.cpu_us):>10}"
        )
    if pyobs is None:
        print(f"{'pyobs-core 2.19.1 RPC':<44} {pyobs_note}")
    ready = statistics.median(starts.ready_s)
    spread = f"{min(starts.ready_s):.3f}..{max(starts.ready_s):.3f}"
    print(
        f"{'nightcrew run → READY (XmppComm), median s':<44} {ready:>9.3f}"
        f"   ({len(starts.ready_s)} starts: {spread})"
    )
    print(f"{'python -c pass (interpreter floor), s':<44} {starts.python_s:>9.3f}")
    print(f"{'idle module RSS after READY + 2 s, MB':<44} {starts.rss_mb:>9.1f}")
    targets = [
        ("median <= 1.1 x raw slixmpp", nightcrew.median_ms <= 1.1 * raw.median_ms),
        ("throughput >= 0.9 x raw slixmpp", nightcrew.calls_per_s >= 0.9 * raw.calls_per_s),
        ("start to READY <= 1 s", ready <= 1.0),
        ("idle module <= 120 MB RSS", starts.rss_mb <= 120.0),
    ]
    if pyobs is not None:
        targets.insert(2, ("throughput >= 2 x pyobs-core", nightcrew.calls_per_s >= 2 * pyobs.calls_per_s))
    for name, met in targets:
        print(f"target: {name:<34} -> {'met' if met else 'MISSED'}")
    if pyobs is None:
        print("target: throughput >= 2 x pyobs-core     -> not measured (no --pyobs-venv)")


async def run_bench(options: argparse.Namespace, directory: Path) -> None:
    port = _free_port()
    accounts = [Account(user, DOMAIN, PASSWORD) for user in USERS]
    init_server(directory, accounts, host="127.0.0.1", port=port, domains=[DOMAIN])
    pid = start_server(directory)
    try:
        server = Server(f"127.0.0.1:{port}", str(directory / "certs" / f"{DOMAIN}.crt"), pid)
        raw = await bench_raw(server, options)
        nightcrew = await bench_nightcrew(server, options)
        pyobs: RpcFigures | None = None
        note = "not measured (give --pyobs-venv PATH)"
        if options.pyobs_venv is not None:
            python = Path(options.pyobs_venv) / "bin" / "python"
            if python.exists():
                pyobs = await bench_pyobs(server, python, options)
            else:
                note = f"not measured: {python} does not exist"
        starts = await bench_start(server, directory, options.starts)
    finally:
        stop_server(directory)
    print_table(raw, nightcrew, pyobs, note, starts)


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--calls", type=int, default=1000, help="sequential calls for the latency")
    parser.add_argument("--concurrency", type=int, default=50, help="calls in flight for the throughput")
    parser.add_argument("--rounds", type=int, default=5, help="throughput rounds (median)")
    parser.add_argument("--starts", type=int, default=5, help="nightcrew run starts (median)")
    parser.add_argument("--pyobs-venv", metavar="PATH", help="a venv with pyobs-core 2.19.1 installed")
    # A child's role (internal): serve as callee until stdin closes.
    parser.add_argument("--role", choices=["adder", "echo"], help=argparse.SUPPRESS)
    parser.add_argument("--server", help=argparse.SUPPRESS)
    parser.add_argument("--ca-file", help=argparse.SUPPRESS)
    options = parser.parse_args()
    if not 1 <= options.starts <= 20:
        parser.error("--starts must be 1..20")
    if options.role is not None:
        server = Server(options.server, options.ca_file)
        asyncio.run(serve_adder(server) if options.role == "adder" else serve_echo(server))
        return
    directory = Path(tempfile.mkdtemp(prefix="nightcrew-bench-"))
    try:
        asyncio.run(run_bench(options, directory))
    except KeyboardInterrupt:
        print("interrupted; server and children stopped", file=sys.stderr)
    finally:
        shutil.rmtree(directory, ignore_errors=True)


if __name__ == "__main__":
    main()
