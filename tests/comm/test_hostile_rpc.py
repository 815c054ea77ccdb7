"""Hostile RPC payloads on every transport: a fault for each bad call, never a crash or a hang.

Seeded generators send thousands of calls with random wire values (deep nesting, NaN and infinity,
large strings and bytes, wrong counts and types, unknown and very long method names). Every call
must end with a result or a nightcrew error; faults and log lines stay short (arguments are never
echoed whole); afterwards the module still answers.
"""

from __future__ import annotations

import logging
import random
import xml.etree.ElementTree as ET
from datetime import UTC, datetime
from typing import Any

import pytest

from nightcrew.comm.rpc import MAX_ARGUMENT_BYTES, MAX_ARGUMENT_DEPTH, MAX_FAULT_CHARS
from nightcrew.comm.xmpp._stanza_limits import MAX_PAYLOAD_BYTES
from nightcrew.comm.xmpp._xmlrpc import build_call, parse_call
from nightcrew.errors import CodecError, InvalidArgumentError, NightcrewError
from nightcrew.log import LogForwarder

from .conftest import Network
from .sample import Calculator
from .xmpp_servers import DOMAIN, XmppServer

METHODS = ["add", "divide", "measure", "echo", "crash", "get_state", "no_such_method", "x" * 5000]


def hostile_value(rng: random.Random, depth: int = 0, *, big: int) -> Any:
    kind = rng.randrange(12 if depth < MAX_ARGUMENT_DEPTH + 8 else 8)
    if kind == 0:
        return rng.choice([float("nan"), float("inf"), float("-inf"), -0.0, 1e308, -1e-308])
    if kind == 1:
        return rng.randint(-(2**63), 2**63 - 1)
    if kind == 2:
        return "".join(chr(rng.randrange(32, 0x2FFF)) for _ in range(rng.randrange(20)))
    if kind == 3:
        return "A" * rng.randrange(big)
    if kind == 4:
        return rng.randbytes(rng.randrange(big // 2))
    if kind == 5:
        return rng.choice([None, True, False, 0, 1, 2.5, "red", "green", ""])
    if kind == 6:
        return datetime(rng.randrange(1, 9999), 1, 1, tzinfo=UTC)
    if kind == 7:
        return rng.random() * 10 ** rng.randrange(-30, 30)
    if kind in (8, 9):  # one long chain, to go past the depth limit
        return [hostile_value(rng, depth + 1, big=big)]
    if kind == 10:
        return [hostile_value(rng, depth + 1, big=big) for _ in range(rng.randrange(4))]
    return {f"k{i}": hostile_value(rng, depth + 1, big=big) for i in range(rng.randrange(4))}


async def _fuzz(network: Network, calls: int, big: int, seed: int) -> dict[str, int]:
    await network.start(Calculator, "calc")
    caller = await network.start(Calculator, "caller")
    rng = random.Random(seed)
    outcomes: dict[str, int] = {}
    for _ in range(calls):
        method = rng.choice(METHODS)
        args = [hostile_value(rng, big=big) for _ in range(rng.randrange(4))]
        try:
            await caller.comm.execute("calc", method, args)
            outcome = "result"
        except NightcrewError as exc:
            outcome = type(exc).__name__
            assert len(exc.message) <= MAX_FAULT_CHARS + 40, exc.message[:200]
        outcomes[outcome] = outcomes.get(outcome, 0) + 1
    # Still alive and correct after all that.
    assert await caller.comm.execute("calc", "add", [2, 3]) == 5
    return outcomes


async def test_hostile_payloads(network: Network, caplog: pytest.LogCaptureFixture) -> None:
    # The forwarder lowers the root level to INFO once per process: installed first, that lasts;
    # installed under caplog, caplog would undo it and later tests' modules forward no records.
    LogForwarder.install()
    caplog.set_level(logging.INFO)
    # Over XMPP the payloads stay small (oversized stanzas are test_raw_hostile_calls_over_prosody's);
    # the in-process transport gets the large ones.
    local = network.kind == "local"
    outcomes = await _fuzz(network, 2000 if local else 500, 200_000 if local else 20_000, seed=9)
    assert outcomes.get("InvalidArgumentError", 0) > 50, outcomes
    assert outcomes.get("result", 0) > 10, outcomes
    assert outcomes.get("InterfaceError", 0) > 10, outcomes
    longest = max((len(record.getMessage()) for record in caplog.records), default=0)
    assert longest < 2 * MAX_FAULT_CHARS, longest


async def test_oversized_argument_gets_a_short_fault(caplog: pytest.LogCaptureFixture) -> None:
    # In-process: over XMPP the caller refuses an oversized call before sending (test below).
    network = Network("local")
    try:
        await network.start(Calculator, "calc")
        caller = await network.start(Calculator, "caller")
        with pytest.raises(
            InvalidArgumentError, match=f"arguments larger than {MAX_ARGUMENT_BYTES} bytes"
        ) as raised:
            await caller.comm.execute("calc", "echo", ["B" * 8 * 1024 * 1024])
    finally:
        await network.close()
    assert len(raised.value.message) < 200
    assert all(len(record.getMessage()) < 1000 for record in caplog.records)


@pytest.mark.parametrize("value", [float("nan"), float("inf"), float("-inf")])
async def test_non_finite_arguments_refused(network: Network, value: float) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Calculator, "caller")
    with pytest.raises(InvalidArgumentError, match=r"add\(\): argument 'a': .* is not a finite number"):
        await caller.comm.execute("calc", "add", [value, 1.0])


#: Every depth up to just past the limit, then deep ones around and far past Python's recursion
#: limit (1000), where a recursive decoder without the bound would raise RecursionError.
_DEPTHS = [
    *range(1, MAX_ARGUMENT_DEPTH + 3),
    100,
    999,
    1000,
    1001,
    2999,
    *random.Random(3).sample(range(34, 3000), 8),
]


@pytest.mark.parametrize("kind", ["array", "struct"])
def test_xml_decoder_bounded_by_depth(kind: str) -> None:
    """A methodCall nested far beyond the limit: CodecError, not a RecursionError."""
    for depth in _DEPTHS:
        if kind == "array":
            inner = (
                "<value><array><data>" * depth
                + "<value><int>1</int></value>"
                + "</data></array></value>" * depth
            )
        else:
            inner = (
                "<value><struct><member><name>a</name>" * depth
                + "<value><nil/></value>"
                + "</member></struct></value>" * depth
            )
        text = (
            '<query xmlns="jabber:iq:rpc"><methodCall><methodName>echo</methodName>'
            f"<params><param>{inner}</param></params></methodCall></query>"
        )
        query = ET.fromstring(text)
        if depth <= MAX_ARGUMENT_DEPTH:
            parse_call(query)
        else:
            with pytest.raises(CodecError, match="nested deeper than"):
                parse_call(query)


@pytest.mark.xmpp
async def test_raw_hostile_calls_over_prosody(
    prosody_server: XmppServer, caplog: pytest.LogCaptureFixture
) -> None:
    """A seeded sample of bench/hostile_rpc.py's raw calls (the bench sends 1,500): every call
    answered, nothing private run, no traceback; oversized and deep calls refused while they
    stream in, with one WARNING naming the sender. (Calls of a million small values are the
    bench's: Prosody alone takes seconds to relay one.)"""
    from bench.hostile_rpc import PASSWORD as BENCH_PASSWORD
    from bench.hostile_rpc import HostileCall, attack, hostile_calls

    calls = [call for call in hostile_calls(seed=26, count=100) if call.kind != "oversized values"]
    calls.append(HostileCall("oversized string", build_call("echo", ["A" * 1_900_000])))
    calls.append(HostileCall("deep event", "[" * 5000 + "]" * 5000))
    for name in ("target", "attacker"):
        prosody_server.account(name, BENCH_PASSWORD)
    report = await attack(prosody_server.address, DOMAIN, calls, ca_file=prosody_server.ca_file)
    assert (report.hangs, report.private_reached, report.tracebacks) == (0, 0, 0), report
    assert report.target_alive
    kinds = {outcome.split(":")[0] for outcome in report.outcomes}
    assert {"deep", "deep event", "private", "oversized string", "malformed", "random"} <= kinds
    refusals = [r.getMessage() for r in caplog.records if r.getMessage().startswith("refused <iq")]
    assert refusals and all(f"from attacker@{DOMAIN}/attack: " in line for line in refusals)
    assert any(line.endswith("larger than 1048576 bytes") for line in refusals)
    assert any("nested deeper than" in line for line in refusals)
    deep_events = [r.getMessage() for r in caplog.records if "its payload is nested deeper" in r.getMessage()]
    assert deep_events and all("from attacker" in line for line in deep_events)


@pytest.mark.xmpp
async def test_an_oversized_call_is_refused_by_its_caller_before_sending(prosody_network: Network) -> None:
    await prosody_network.start(Calculator, "calc")
    caller = await prosody_network.start(Calculator, "caller")
    with pytest.raises(
        InvalidArgumentError, match=f"echo\\(\\): the call is larger than {MAX_PAYLOAD_BYTES} bytes"
    ):
        await caller.comm.execute("calc", "echo", ["B" * 1_500_000])
    assert await caller.comm.execute("calc", "add", [2, 3]) == 5
