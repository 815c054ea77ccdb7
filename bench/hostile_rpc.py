"""Hostile remote calls over Prosody: every one refused cleanly, nothing private reached, no stall.

A seeded generator writes raw ``jabber:iq:rpc`` calls as an attacker would, not as nightcrew's
caller would (which refuses oversized calls before sending): random and wrong-typed values,
non-finite numbers, malformed XML-RPC, private and unknown method names, calls of 1.1 to 1.9 MB
of small values or one long string (past the module's 1-MiB limit, within the 2 MiB at which
Prosody itself ends the sender's stream), values nested up to 5,000 deep, and events nested as deep. An
attacker account sends them one at a time to a target module on a private Prosody; a ticker task
measures the target's event-loop lag. Both run in this process (the payloads are written before
the clock starts, so the attacker's cost is a socket write per call).

Counted: outcomes per kind, calls unanswered within 15 s (hangs), calls of methods outside the
target's interfaces that ran (private reached), ticks late by over 100 ms, tracebacks logged.

    .venv/bin/python bench/hostile_rpc.py [--calls 1500] [--seed 26]
"""

from __future__ import annotations

import argparse
import asyncio
import base64
import itertools
import logging
import random
import tempfile
import time
import xml.etree.ElementTree as ET
from abc import abstractmethod
from collections import Counter
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from nightcrew.comm.rpc import Fault
from nightcrew.comm.xmpp import XmppComm
from nightcrew.comm.xmpp._connection import XmppConnection
from nightcrew.comm.xmpp._settings import XmppSettings
from nightcrew.comm.xmpp._xmlrpc import build_call, parse_response
from nightcrew.comm.xmpp._xmltext import escape_text
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module
from nightcrew.server import Account, init_server, register_account, start_server, stop_server

DOMAIN = "hostile.test"
PASSWORD = "hostile-secret"
ROOM = "hostile"
_NS_C = "{jabber:client}"
_NS_RPC = "{jabber:iq:rpc}"
_REPLY_TIMEOUT = 15.0
STALL = 0.1  # seconds of event-loop lag that count as a stall
_TICK = 0.01


class IHostileTarget(Interface):
    """What the target serves."""

    @abstractmethod
    async def add(self, a: float, b: float) -> float: ...

    @abstractmethod
    async def echo(self, value: Any) -> Any: ...


class HostileTarget(Module, IHostileTarget):
    """Serves IHostileTarget; counts every run of a method no interface declares."""

    private_reached = 0

    async def add(self, a: float, b: float) -> float:
        return a + b

    async def echo(self, value: Any) -> Any:
        return value

    async def _secret(self, *args: Any) -> None:
        HostileTarget.private_reached += 1

    async def reset(self, *args: Any) -> None:  # public, but in no interface
        HostileTarget.private_reached += 1


_PRIVATE = [
    "_secret",
    "__init__",
    "reset",
    "open",
    "close",
    "_comm",
    "__class__",
    "system._secret",
    "_handle",
]
_METHODS = ["add", "echo", "no_such_method", "system.describe", "x" * 3000, *_PRIVATE]


@dataclass(frozen=True)
class HostileCall:
    kind: str
    payload: str  # the query element, or a whole groupchat message for kind "deep event"


def _value(rng: random.Random, depth: int = 0) -> str:
    kind = rng.randrange(10 if depth < 40 else 7)
    if kind == 0:
        return f"<value><double>{rng.choice(['nan', 'inf', '-inf', '1e999', '-0.0', 'x'])}</double></value>"
    if kind == 1:
        return f"<value><int>{rng.choice([2**63, -(2**70), 7, '1.5', ''])}</int></value>"
    if kind == 2:
        text = "".join(chr(rng.randrange(32, 0x2FFF)) for _ in range(20))
        return f"<value><string>{escape_text(text)}</string></value>"
    if kind == 3:
        return (
            f"<value><base64>{base64.b64encode(rng.randbytes(rng.randrange(200))).decode()}</base64></value>"
        )
    if kind == 4:
        return rng.choice(
            ["<value><nil/></value>", "<value><boolean>2</boolean></value>", "<value>bare</value>"]
        )
    if kind == 5:
        return rng.choice(
            [
                "<value><dateTime.iso8601>99999999T99:99:99</dateTime.iso8601></value>",
                "<value><blob/></value>",
            ]
        )
    if kind == 6:
        return "<value><struct><member><value><int>1</int></value></member></struct></value>"  # no name
    if kind == 7:
        items = "".join(_value(rng, depth + 1) for _ in range(rng.randrange(3)))
        return f"<value><array><data>{items}</data></array></value>"
    if kind == 8:
        return f"<value><array><data>{_value(rng, depth + 1)}</data></array></value>"
    return f"<value><struct><member><name>k</name>{_value(rng, depth + 1)}</member></struct></value>"


def _query(method: str, values: list[str]) -> str:
    params = "".join(f"<param>{value}</param>" for value in values)
    return (
        f'<query xmlns="jabber:iq:rpc"><methodCall><methodName>{escape_text(method)}</methodName>'
        f"<params>{params}</params></methodCall></query>"
    )


def _deep(depth: int) -> str:
    return "<value><array><data>" * depth + "<value><int>1</int></value>" + "</data></array></value>" * depth


def hostile_calls(seed: int, count: int) -> Iterator[HostileCall]:
    """``count`` hostile calls, the same for the same seed."""
    rng = random.Random(seed)
    for _ in range(count):
        roll = rng.random()
        if roll < 0.04:
            size = rng.randrange(1_100_000, 1_900_000)
            if rng.random() < 0.5:
                yield HostileCall("oversized string", build_call("echo", ["A" * size]))
            else:
                yield HostileCall("oversized values", build_call("echo", [[0] * (size // 25)]))
        elif roll < 0.08:
            yield HostileCall("deep", _query("echo", [_deep(rng.choice([40, 60, 1000, 5000]))]))
        elif roll < 0.10:
            depth = rng.choice([40, 1000, 5000])
            yield HostileCall("deep event", "[" * depth + "]" * depth)
        elif roll < 0.14:
            yield HostileCall(
                "malformed",
                rng.choice(
                    [
                        '<query xmlns="jabber:iq:rpc"/>',
                        '<query xmlns="jabber:iq:rpc"><methodCall/></query>',
                        _query("add", ["<value><int>x</int></value>"] * 2),
                    ]
                ),
            )
        elif roll < 0.30:
            yield HostileCall(
                "private", _query(rng.choice(_PRIVATE), [_value(rng) for _ in range(rng.randrange(3))])
            )
        else:
            method = rng.choice(_METHODS)
            yield HostileCall("random", _query(method, [_value(rng) for _ in range(rng.randrange(4))]))


@dataclass
class Report:
    outcomes: Counter[str] = field(default_factory=Counter)
    hangs: int = 0
    private_reached: int = 0
    stalls: int = 0  # ticks late by over STALL while this process worked over STALL
    late_ticks: int = 0  # ticks late by over STALL, for whatever reason
    max_lag: float = 0.0
    max_busy: float = 0.0
    tracebacks: int = 0
    target_alive: bool = False


class _Attacker:
    """A raw XMPP session that sends queries as written and waits for what comes back."""

    def __init__(self, settings: XmppSettings) -> None:
        self.connection = XmppConnection(
            settings, on_session=self._nothing, on_lost=lambda: None, features=[]
        )
        self.connection.add_handler("replies", f"{_NS_C}iq", self._on_iq)
        self._waiting: dict[str, asyncio.Future[str]] = {}
        self._ids = itertools.count()

    async def _nothing(self) -> None:
        return None

    def _on_iq(self, stanza: ET.Element) -> bool:
        future = self._waiting.pop(stanza.get("id", ""), None)
        if future is None or future.done():
            return False
        if stanza.get("type") == "error":
            future.set_result("iq error")
            return True
        query = stanza.find(f"{_NS_RPC}query")
        reply = parse_response(query) if query is not None else None
        future.set_result(reply.error_class if isinstance(reply, Fault) else "result")
        return True

    async def call(self, to: str, query: str) -> str:
        iq_id = f"h{next(self._ids)}"
        future: asyncio.Future[str] = asyncio.get_running_loop().create_future()
        self._waiting[iq_id] = future
        self.connection.send_text("iq", to, query, id=iq_id, type="set")
        try:
            return await asyncio.wait_for(future, _REPLY_TIMEOUT)
        finally:
            self._waiting.pop(iq_id, None)

    async def join(self, room: str) -> None:
        self.connection.send_text(
            "presence", f"{room}/attacker", '<x xmlns="http://jabber.org/protocol/muc"/>'
        )
        await asyncio.sleep(0.2)  # the room answers with presences nobody here waits for

    def event(self, room: str, text: str) -> None:
        body = f'<event xmlns="urn:nightcrew:event" name="TestEvent">{escape_text(text)}</event>'
        self.connection.send_text("message", room, body, type="groupchat")


class _Tracebacks(logging.Handler):
    def __init__(self) -> None:
        super().__init__(logging.WARNING)
        self.count = 0
        self.refusals: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        if record.exc_info:
            self.count += 1
        if record.levelno == logging.WARNING:
            self.refusals.append(record.getMessage())


async def attack(
    address: str, domain: str, calls: list[HostileCall], *, ca_file: str | None, password: str = PASSWORD
) -> Report:
    """Start the target, send ``calls`` from the attacker account, count what happened."""
    report = Report()
    HostileTarget.private_reached = 0
    room = f"{ROOM}@conference.{domain}"
    target = HostileTarget(  # `policy: open`, the worst case: every call reaches argument decoding
        comm=XmppComm(f"target@{domain}", password, server=address, room=ROOM, ca_file=ca_file, policy="open")
    )
    settings = XmppSettings.from_options(
        f"attacker@{domain}", password, server=address, room=ROOM, ca_file=ca_file, resource="attack"
    )
    attacker = _Attacker(settings)
    logs = _Tracebacks()
    logging.getLogger().addHandler(logs)
    await target.open()
    await attacker.connection.open()
    await attacker.join(room)
    lags: list[float] = []
    busy: list[float] = []
    ticker = asyncio.create_task(_ticker(lags, busy))
    try:
        for call in calls:
            if call.kind == "deep event":
                attacker.event(room, call.payload)
                await asyncio.sleep(_TICK)
                report.outcomes["deep event"] += 1
                continue
            try:
                report.outcomes[
                    f"{call.kind}: {await attacker.call(f'target@{domain}/nightcrew', call.payload)}"
                ] += 1
            except TimeoutError:
                report.hangs += 1
                report.outcomes[f"{call.kind}: no answer"] += 1
        report.target_alive = (
            await attacker.call(f"target@{domain}/nightcrew", build_call("add", [2.0, 3.0])) == "result"
        )
    finally:
        ticker.cancel()
        await attacker.connection.close()
        await target.close()
        logging.getLogger().removeHandler(logs)
    report.private_reached = HostileTarget.private_reached
    report.late_ticks = sum(lag > STALL for lag in lags)
    report.stalls = sum(lag > STALL and cpu > STALL for lag, cpu in zip(lags, busy, strict=False))
    report.max_lag = max(lags, default=0.0)
    report.max_busy = max(busy, default=0.0)
    report.tracebacks = logs.count
    return report


async def _ticker(lags: list[float], busy: list[float]) -> None:
    """Lag of each tick, and the CPU time this process used in it (on a shared machine a late
    tick may be another process's doing: only CPU time used here is this loop held by work)."""
    loop = asyncio.get_running_loop()
    while True:
        before, cpu = loop.time(), time.process_time()
        await asyncio.sleep(_TICK)
        lags.append(loop.time() - before - _TICK)
        busy.append(time.process_time() - cpu)


@asynccontextmanager
async def private_prosody(domain: str = DOMAIN) -> AsyncIterator[tuple[str, str]]:
    """A Prosody from ``nightcrew server init`` with the target's and attacker's accounts."""
    import socket

    with tempfile.TemporaryDirectory() as name, socket.socket() as probe:
        directory = Path(name)
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
        probe.close()
        init_server(directory, [], host="127.0.0.1", port=port, domains=[domain])
        for user in ("target", "attacker"):
            register_account(directory, Account(user, domain, PASSWORD))
        start_server(directory)
        try:
            yield f"127.0.0.1:{port}", str(directory / "certs" / f"{domain}.crt")
        finally:
            stop_server(directory)


def print_table(report: Report, calls: int, seed: int) -> None:
    print(f"hostile RPC calls over Prosody: {calls} (seed {seed})")
    print(f"{'outcome':<40} {'count':>6}")
    for outcome, count in sorted(report.outcomes.items()):
        print(f"{outcome:<40} {count:>6}")
    print(f"{'hangs (no answer within 15 s)':<40} {report.hangs:>6}")
    print(f"{'private methods reached':<40} {report.private_reached:>6}")
    print(f"{'tracebacks logged':<40} {report.tracebacks:>6}")
    print(f"{'loop stalls > 100 ms (busy here)':<40} {report.stalls:>6}")
    print(f"{'ticks late > 100 ms (any cause)':<40} {report.late_ticks:>6}")
    print(f"{'largest tick lag (ms)':<40} {report.max_lag * 1000:>6.0f}")
    print(f"{'largest CPU time in one tick (ms)':<40} {report.max_busy * 1000:>6.0f}")
    print(f"{'target answers afterwards':<40} {report.target_alive!s:>6}")


async def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--calls", type=int, default=1500)
    parser.add_argument("--seed", type=int, default=26)
    options = parser.parse_args()
    logging.basicConfig(level=logging.WARNING)
    logging.getLogger("nightcrew").setLevel(logging.WARNING)  # refusals yes, every failed call no
    calls = list(hostile_calls(options.seed, options.calls))
    started = time.perf_counter()
    async with private_prosody() as (address, ca_file):
        report = await attack(address, DOMAIN, calls, ca_file=ca_file)
    print_table(report, options.calls, options.seed)
    print(f"{'wall seconds':<40} {time.perf_counter() - started:>6.0f}")


if __name__ == "__main__":
    asyncio.run(main())
