"""In-process comm benchmark: RPC µs per call and events per second on LocalComm.

Prints one table. The baseline row is a plain ``await`` of the same coroutine method without any
comm, measured in the same run, so the ratio shows what the comm adds.

    .venv/bin/python bench/local_rpc.py [--calls 20000] [--events 20000]
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import time
from abc import abstractmethod
from typing import Any

from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.events import TestEvent
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module


class IBenchAdder(Interface):
    @abstractmethod
    async def add(self, a: float, b: float) -> float: ...


class Adder(Module, IBenchAdder):
    async def add(self, a: float, b: float) -> float:
        return a + b


class Counter(Module):
    def __init__(self, expected: int, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.count = 0
        self.expected = expected
        self.done = asyncio.Event()

    async def on_event(self, event: TestEvent, sender: str) -> None:
        self.count += 1
        if self.count == self.expected:
            self.done.set()


async def _per_call_us(call: Any, n: int, repeats: int = 5) -> float:
    """Median over ``repeats`` runs of the mean µs per call of ``n`` sequential calls."""
    runs = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(n):
            await call(1.0, 2.0)
        runs.append((time.perf_counter() - start) / n * 1e6)
    return statistics.median(runs)


async def main(calls: int, events: int) -> None:
    network = LocalNetwork()
    adder = Adder(comm=LocalComm("adder", network=network))
    caller = Module(comm=LocalComm("caller", network=network))
    counter = Counter(events, comm=LocalComm("counter", network=network))
    for module in (adder, caller, counter):
        await module.open()
    await counter.comm.register_event(TestEvent, counter.on_event)
    proxy = await caller.comm.proxy("adder", IBenchAdder)

    baseline = await _per_call_us(adder.add, calls)
    rpc = await _per_call_us(proxy.add, calls)

    start = time.perf_counter()
    for _ in range(events):
        await caller.comm.send_event(TestEvent(message="x"))
    await asyncio.wait_for(counter.done.wait(), 60)
    events_per_s = events / (time.perf_counter() - start)

    for module in (counter, caller, adder):
        await module.close()

    print(f"{'measurement':<38} {'value':>12} {'vs baseline':>12}")
    print(f"{'direct await (baseline), µs/call':<38} {baseline:>12.2f} {1.0:>11.1f}x")
    print(f"{'LocalComm RPC via proxy, µs/call':<38} {rpc:>12.2f} {rpc / baseline:>11.1f}x")
    print(f"{'LocalComm events sent+handled, 1/s':<38} {events_per_s:>12.0f} {'':>12}")
    print(f"target: RPC <= 30 µs/call -> {'met' if rpc <= 30 else 'MISSED'}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=20000)
    parser.add_argument("--events", type=int, default=20000)
    options = parser.parse_args()
    asyncio.run(main(options.calls, options.events))
