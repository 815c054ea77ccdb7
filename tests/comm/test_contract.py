"""The comm contract: what every transport must do the same way (run per transport)."""

from __future__ import annotations

import asyncio
import logging
import time
from abc import abstractmethod
from datetime import UTC, datetime

import pytest

from nightcrew.clock import AcceleratedClock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.errors import (
    CodecError,
    ConfigError,
    InterfaceError,
    InvalidArgumentError,
    ModuleError,
    RemoteError,
    RemoteTimeoutError,
)
from nightcrew.events import LogEvent, ModuleClosedEvent, ModuleOpenedEvent, TestEvent
from nightcrew.interfaces import IModule, ModuleState
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module
from nightcrew.timeout import timeout

from .conftest import Network
from .sample import Calculator, Colour, ICalculator, ISlow, Listener, Measurement


async def test_proxy_is_instance_of_remote_interfaces(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    proxy = await caller.comm.proxy("calc", ICalculator)
    assert isinstance(proxy, ICalculator)
    assert isinstance(proxy, ISlow)
    assert isinstance(proxy, IModule)
    assert await proxy.add(2, 3) == 5.0
    assert await proxy.add(2) == 3.0  # default filled in by the caller
    assert await proxy.add(a=1.5, b=2.5) == 4.0


async def test_rich_values_round_trip(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    proxy = await caller.comm.proxy("calc", ICalculator)
    assert await proxy.measure(Colour.GREEN) == Measurement(value=42.5, unit="adu", colour=Colour.GREEN)
    when = datetime(2026, 11, 22, 21, 30, tzinfo=UTC)
    value = {"n": [1, 2.5, None, True], "s": "ä", "b": b"\x00\xff", "t": when}
    assert await proxy.echo(value) == value


async def test_remote_exception_keeps_its_class_and_module(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    proxy = await caller.comm.proxy("calc", ICalculator)
    with pytest.raises(InvalidArgumentError, match="division by zero") as info:
        await proxy.divide(1, 0)
    assert info.value.module == "calc"
    assert str(info.value) == "calc: division by zero"


async def test_unexpected_remote_exception_arrives_as_remote_error(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    proxy = await caller.comm.proxy("calc", ICalculator)
    with pytest.raises(RemoteError, match="ValueError: bug in the callee") as info:
        await proxy.crash()
    assert type(info.value) is RemoteError


async def test_wrong_argument_type_is_refused_by_callee(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    with pytest.raises(InvalidArgumentError, match=r"add\(\): argument 'a': expected number, got string"):
        await caller.comm.execute("calc", "add", ["two", 1.0])
    with pytest.raises(InterfaceError, match="no method 'subtract'"):
        await caller.comm.execute("calc", "subtract", [1.0, 2.0])


async def test_values_that_cannot_travel_are_refused_in_process_too(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    proxy = await caller.comm.proxy("calc", ICalculator)
    with pytest.raises(CodecError, match=r"argument 'value'.*type object cannot be sent"):
        await proxy.echo(object())
    with pytest.raises(CodecError, match="dict keys must be strings"):
        await proxy.echo({1: "one"})


async def test_timeout_announced_by_callee_is_enforced(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    proxy = await caller.comm.proxy("calc", ISlow)
    started = time.monotonic()
    with pytest.raises(RemoteTimeoutError, match=r"too_slow\(\) did not finish within 0.3 s") as info:
        await proxy.too_slow()
    assert info.value.module == "calc"
    assert time.monotonic() - started < 0.3 + 2.5  # announced timeout + at most the transport grace


async def test_announced_timeout_extends_beyond_the_default(network: Network) -> None:
    # On the caller's clock at speed 20, the 10-s default wait is 0.5 s of wall time. The call takes
    # 0.8 s of wall time and succeeds only because the callee announces 80 clock s (4 s of wall).
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller", clock=AcceleratedClock("2026-11-22T20:00:00", speed=20))
    proxy = await caller.comm.proxy("calc", ISlow)
    assert await proxy.wait(0.8) == 0.8


async def test_proxy_for_missing_interface_or_module(network: Network) -> None:
    await network.start(Module, "plain")
    caller = await network.start(Module, "caller")
    with pytest.raises(InterfaceError, match="module 'plain' does not offer ICalculator"):
        await caller.comm.proxy("plain", ICalculator)
    with pytest.raises(RemoteError, match="'ghost' is not online"):
        await caller.comm.proxy("ghost", ICalculator)


async def test_a_caller_waits_boundedly_for_a_module_to_come_online(network: Network) -> None:
    caller = await network.start(Module, "caller")
    assert not await caller.comm.wait_for_client("calc", 0.2)  # nobody of that name: gives up
    waiting = asyncio.create_task(caller.comm.wait_for_client("calc", 30.0))
    await network.start(Calculator, "calc")
    assert await asyncio.wait_for(waiting, 30.0)  # returns when it comes, not after the bound


async def test_clients_and_interface_discovery(network: Network) -> None:
    await network.start(Calculator, "calc")
    await network.start(Module, "plain")
    caller = await network.start(Module, "caller")
    assert set(caller.comm.clients) >= {"calc", "plain"}
    assert await caller.comm.clients_with_interface(ICalculator) == ["calc"]
    assert set(await caller.comm.clients_with_interface(IModule)) >= {"calc", "plain"}


async def test_events_reach_registered_modules_and_can_chain(network: Network) -> None:
    listener = await network.start(Listener, "listener")
    sender = await network.start(Listener, "sender")
    await sender.comm.send_event(TestEvent(message="ping"))
    await asyncio.wait_for(listener.arrived.wait(), 5)
    assert listener.received == [(TestEvent(message="ping"), "sender")]
    # the listener answered with "pong", which the sender receives in turn
    await asyncio.wait_for(sender.arrived.wait(), 5)
    assert sender.received == [(TestEvent(message="pong"), "listener")]


async def test_online_and_offline_notifications(network: Network) -> None:
    watcher = await network.start(Module, "watcher")
    seen: list[tuple[str, str]] = []
    changed = asyncio.Event()

    async def on_presence(event: ModuleOpenedEvent | ModuleClosedEvent, sender: str) -> None:
        seen.append((type(event).__name__, sender))
        changed.set()

    await watcher.comm.register_event(ModuleOpenedEvent, on_presence)
    await watcher.comm.register_event(ModuleClosedEvent, on_presence)
    other = await network.start(Module, "other")
    await asyncio.wait_for(changed.wait(), 5)
    changed.clear()
    await other.close()
    await asyncio.wait_for(changed.wait(), 5)
    assert seen == [("ModuleOpenedEvent", "other"), ("ModuleClosedEvent", "other")]
    assert "other" not in watcher.comm.clients


async def test_log_records_are_forwarded_as_log_events(network: Network) -> None:
    calc = await network.start(Calculator, "calc")
    viewer = await network.start(Module, "viewer")
    got: list[tuple[LogEvent, str]] = []
    arrived = asyncio.Event()

    async def on_log(event: LogEvent, sender: str) -> None:
        if "hello from calc" in event.message:
            got.append((event, sender))
            arrived.set()

    await viewer.comm.register_event(LogEvent, on_log)

    async def log_something() -> None:
        logging.getLogger("tests.calc").info("hello from calc")

    calc.add_background_task(log_something, restart=False)
    await asyncio.wait_for(arrived.wait(), 5)
    event, sender = got[0]
    assert sender == "calc" and event.level == "INFO" and event.logger == "tests.calc"


async def test_log_records_from_a_worker_thread_are_forwarded(network: Network) -> None:
    # asyncio.to_thread copies the module's context into the thread: its records count as the
    # module's, and reach the bus through the module's loop.
    calc = await network.start(Calculator, "calc")
    viewer = await network.start(Module, "viewer")
    arrived = asyncio.Event()

    async def on_log(event: LogEvent, sender: str) -> None:
        if "hello from a thread" in event.message and sender == "calc":
            arrived.set()

    await viewer.comm.register_event(LogEvent, on_log)

    async def log_from_a_thread() -> None:
        await asyncio.to_thread(logging.getLogger("tests.calc").warning, "hello from a thread")

    calc.add_background_task(log_from_a_thread, restart=False)
    await asyncio.wait_for(arrived.wait(), 5)


async def test_error_limit_puts_module_in_error_state_until_reset(network: Network) -> None:
    calc = await network.start(Calculator, "calc")
    calc.register_exception(InvalidArgumentError, 2, timespan=60)
    caller = await network.start(Module, "caller")
    proxy = await caller.comm.proxy("calc", ICalculator)
    for _ in range(2):
        with pytest.raises(InvalidArgumentError):
            await proxy.divide(1, 0)
    assert calc.state is ModuleState.ERROR
    with pytest.raises(ModuleError, match="error state: too many InvalidArgumentError"):
        await proxy.add(1, 1)
    module = await caller.comm.proxy("calc", IModule)
    assert await module.get_state() is ModuleState.ERROR
    assert await module.reset_error() is True
    assert await proxy.add(1, 1) == 2.0


async def test_caller_counts_errors_of_a_named_remote_module(network: Network) -> None:
    await network.start(Calculator, "calc")
    caller = await network.start(Module, "caller")
    escalated: list[BaseException] = []
    caller.register_exception(RemoteError, 1, module="calc", callback=escalated.append)
    proxy = await caller.comm.proxy("calc", ICalculator)
    with pytest.raises(RemoteError):
        await proxy.crash()
    assert len(escalated) == 1 and escalated[0].module == "calc"  # type: ignore[attr-defined]


async def test_a_local_network_grace_gives_calls_wall_time_beyond_their_timeout() -> None:
    # too_slow() declares 0.3 s and sleeps 5 s: with 0.5 s of grace it fails after ~0.8 s, not 0.3.
    for grace, least, most in ((0.0, 0.25, 0.6), (0.5, 0.75, 1.2)):
        network = LocalNetwork(rpc_grace=grace)
        calc = Calculator(comm=LocalComm("calc", network=network))
        caller = Module(comm=LocalComm("caller", network=network))
        await calc.open()
        await caller.open()
        try:
            slow = await caller.comm.proxy("calc", ISlow)
            started = time.monotonic()
            with pytest.raises(RemoteTimeoutError):
                await slow.too_slow()
            assert least < time.monotonic() - started < most
        finally:
            await caller.close()
            await calc.close()
    with pytest.raises(ConfigError, match="rpc_grace"):
        LocalNetwork(rpc_grace=-1)


class IComputing(Interface):
    """A method whose callee computes (at real time) for a while."""

    @abstractmethod
    @timeout(lambda wall_seconds, limit, **_: limit)
    async def solve(self, wall_seconds: float, limit: float) -> float: ...


class Computing(Module, IComputing):
    async def solve(self, wall_seconds: float, limit: float) -> float:
        with self.clock.computing():
            await asyncio.sleep(wall_seconds)
        return wall_seconds


async def test_a_call_waits_in_clock_seconds_while_the_callee_computes() -> None:
    # At speed 100 a 10-s limit is 0.1 s of wall time, but 0.4 s of computing moves the clock
    # by only 0.4 s: the call is in time. A 0.2-s limit is still exceeded by 0.5 s of computing.
    clock = AcceleratedClock("2026-11-22T18:00:00", speed=100)
    network = LocalNetwork()
    callee = Computing(clock=clock, comm=LocalComm("callee", network=network))
    caller = Module(clock=clock, comm=LocalComm("caller", network=network))
    await callee.open()
    await caller.open()
    try:
        proxy = await caller.comm.proxy("callee", IComputing)
        assert await proxy.solve(0.4, 10.0) == 0.4
        with pytest.raises(RemoteTimeoutError):
            await proxy.solve(0.5, 0.2)
    finally:
        await caller.close()
        await callee.close()
