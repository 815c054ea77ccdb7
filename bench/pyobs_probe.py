"""pyobs-core side of bench/rpc.py: the same ``add(a, b)`` RPC measured between two pyobs modules.

Runs in a venv with pyobs-core installed (not nightcrew's), started by ``bench/rpc.py
--pyobs-venv PATH``; written against pyobs' public API (Module, Interface, XmppComm, proxy).

    python pyobs_probe.py serve --user pyadder ...    # prints "ready", serves until stdin closes
    python pyobs_probe.py call --user pycaller --callee pyadder ...   # prints one JSON line

pyobs discovers peers by roster presence, so both accounts must be subscribed to each other
(bench/rpc.py does that before starting this). Its XmppComm connects without TLS here: it turns
on direct TLS together with STARTTLS, which the bench's Prosody (STARTTLS on one port) refuses.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import logging
import statistics
import sys
import time
from abc import ABCMeta, abstractmethod
from collections.abc import Awaitable, Callable
from typing import Any

from pyobs.comm.xmpp import XmppComm  # type: ignore[import-not-found]
from pyobs.interfaces import Interface  # type: ignore[import-not-found]
from pyobs.modules import Module  # type: ignore[import-not-found]


class IBenchAdder(Interface, metaclass=ABCMeta):  # type: ignore[misc]
    @abstractmethod
    async def add(self, a: float, b: float, **kwargs: Any) -> float: ...


class PyAdder(Module, IBenchAdder):  # type: ignore[misc]
    async def add(self, a: float, b: float, **kwargs: Any) -> float:
        return a + b


def _comm(options: argparse.Namespace) -> Any:
    return XmppComm(
        jid=f"{options.user}@{options.domain}",
        password=options.password,
        server=options.server,
        use_tls=False,
    )


async def serve(options: argparse.Namespace) -> None:
    adder = PyAdder(comm=_comm(options))
    await adder.startup()  # open + READY (pyobs refuses calls before READY)
    try:
        print("ready", flush=True)
        await asyncio.get_running_loop().run_in_executor(None, sys.stdin.buffer.read)
    finally:
        await adder.close()


async def call(options: argparse.Namespace) -> None:
    caller = Module(comm=_comm(options))
    await caller.startup()
    try:
        async with caller.comm.proxy(options.callee, IBenchAdder) as adder:
            figures = await measure(
                lambda: adder.add(1.0, 2.0), options.calls, options.concurrency, options.rounds
            )
    finally:
        await caller.close()
    print(json.dumps(figures), flush=True)


async def measure(
    call: Callable[[], Awaitable[Any]], calls: int, concurrency: int, rounds: int
) -> dict[str, float]:
    """The same procedure as bench/rpc.py's ``measure`` (that file needs nightcrew, this venv lacks it)."""
    for _ in range(min(100, calls)):
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
    # bench/rpc.py adds the callee's and server's CPU time at each mark.
    print(f"mark {time.process_time()!r}", flush=True)
    for _ in range(rounds):
        start = time.perf_counter()
        await asyncio.gather(*(worker() for _ in range(concurrency)))
        rates.append(per_worker * concurrency / (time.perf_counter() - start))
    print(f"mark {time.process_time()!r}", flush=True)
    return {
        "throughput_calls": rounds * per_worker * concurrency,
        "median_ms": statistics.median(latencies) * 1e3,
        "p99_ms": statistics.quantiles(latencies, n=100)[98] * 1e3,
        "calls_per_s": statistics.median(rates),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("role", choices=["serve", "call"])
    parser.add_argument("--user", required=True)
    parser.add_argument("--callee", default="pyadder")
    parser.add_argument("--server", required=True)
    parser.add_argument("--domain", required=True)
    parser.add_argument("--password", required=True)
    parser.add_argument("--calls", type=int, default=1000)
    parser.add_argument("--concurrency", type=int, default=50)
    parser.add_argument("--rounds", type=int, default=5)
    options = parser.parse_args()
    logging.basicConfig(level=logging.WARNING, stream=sys.stderr)
    asyncio.run(serve(options) if options.role == "serve" else call(options))


if __name__ == "__main__":
    main()
