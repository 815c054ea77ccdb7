"""Module and Object behaviour: background tasks, lifecycle, IConfig over the comm."""

from __future__ import annotations

import asyncio
from typing import Any

import pytest

from nightcrew import __version__
from nightcrew.clock import VirtualClock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.errors import ConfigError, InvalidArgumentError, ModuleError
from nightcrew.interfaces import IConfig, IModule, ModuleState
from nightcrew.modules import Module
from nightcrew.modules.module import TRANSITIONS
from nightcrew.modules.test import StandAlone
from nightcrew.object import Object
from nightcrew.testing import modules_ready, wait_for


class Flaky(Module):
    """A module whose background task crashes twice, then settles."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.starts: list[float] = []
        self.settled = asyncio.Event()
        self.add_background_task(self._loop)

    async def _loop(self) -> None:
        self.starts.append(self.clock.time())
        if len(self.starts) <= 2:
            raise RuntimeError(f"crash {len(self.starts)}")
        self.settled.set()
        await self.clock.sleep(3600)


async def test_crashed_background_task_is_restarted_with_growing_delays(
    caplog: pytest.LogCaptureFixture,
) -> None:
    clock = VirtualClock("2026-11-22T18:00:00")  # the delays in clock seconds, whatever the load
    module = Flaky(name="flaky", clock=clock, comm=LocalComm("flaky", network=LocalNetwork()))
    await module.open()
    try:
        await asyncio.wait_for(module.settled.wait(), 5)
    finally:
        await module.close()
    first, second = module.starts[1] - module.starts[0], module.starts[2] - module.starts[1]
    assert first == pytest.approx(1.0, abs=0.5)  # clock seconds
    assert second == pytest.approx(2.0, abs=0.5)
    crashes = [r for r in caplog.records if "crashed; restarting" in r.getMessage()]
    assert len(crashes) == 2 and crashes[0].exc_info is not None


async def test_close_is_safe_twice_and_states_follow_the_table() -> None:
    module = StandAlone(name="hello", interval=1, comm=LocalComm("hello", network=LocalNetwork()))
    seen: list[tuple[ModuleState, ModuleState]] = []
    module.on_state_changed = lambda old, new: seen.append((old, new))  # type: ignore[method-assign]
    await module.open()
    await module.close()
    await module.close()
    assert seen == [
        (ModuleState.STARTING, ModuleState.READY),
        (ModuleState.READY, ModuleState.CLOSING),
        (ModuleState.CLOSING, ModuleState.CLOSED),
    ]
    assert all(new in TRANSITIONS[old] for old, new in seen)
    with pytest.raises(ModuleError, match="cannot go from closed to ready"):
        module._enter(ModuleState.READY)


async def test_config_values_read_and_changed_through_a_proxy() -> None:
    network = LocalNetwork()
    hello = StandAlone(message="hi", interval=5, comm=LocalComm("hello", network=network))
    caller = Module(comm=LocalComm("caller", network=network))
    await hello.open()
    await caller.open()
    try:
        config = await caller.comm.proxy("hello", IConfig)
        assert await config.get_config_caps() == {
            "interval": (True, True, False),
            "message": (True, True, False),
        }
        assert await config.get_config_value("message") == "hi"
        await config.set_config_value("message", "bye")
        assert await config.get_config_value("message") == "bye"
        with pytest.raises(
            InvalidArgumentError, match=r"config option .interval.: -1 is out of range \(must be >= 0.01 s\)"
        ):
            await config.set_config_value("interval", -1)
        with pytest.raises(InvalidArgumentError, match="config option 'colour' is not readable"):
            await config.get_config_value("colour")
    finally:
        await caller.close()
        await hello.close()


def test_module_names() -> None:
    with pytest.raises(ConfigError, match="a module without a comm needs a name"):
        Module()
    with pytest.raises(ConfigError, match="name 'a' differs from the comm's name 'b'"):
        Module(name="a", comm=LocalComm("b", network=LocalNetwork()))
    with pytest.raises(ConfigError, match="interval must be > 0 seconds"):
        StandAlone(name="x", interval=0)


async def test_two_modules_with_one_name_cannot_join_a_network() -> None:
    network = LocalNetwork()
    first = Module(comm=LocalComm("same", network=network))
    await first.open()
    try:
        with pytest.raises(ConfigError, match="a module named 'same' is already running"):
            await Module(comm=LocalComm("same", network=network)).open()
    finally:
        await first.close()


class _SlowToOpen(Object):
    """A child whose opening waits for the test: its module stays starting, already on the network."""

    def __init__(self) -> None:
        super().__init__()
        self.release = asyncio.Event()

    async def open(self) -> None:
        await self.release.wait()
        await super().open()


async def test_who_and_how_a_module_is_answers_while_it_is_starting() -> None:
    network = LocalNetwork()
    starting = Module(comm=LocalComm("starting", network=network), label="Slow starter")
    child = starting.add_child(_SlowToOpen())
    caller = Module(comm=LocalComm("caller", network=network))
    await caller.open()
    opening = asyncio.create_task(starting.open())
    try:
        await wait_for(lambda: "starting" in caller.comm.clients, 5, message="the module on the network")
        module = await caller.comm.proxy("starting", IModule)
        assert await module.get_state() is ModuleState.STARTING
        assert await module.get_label() == "Slow starter"
        assert await module.get_version() == __version__
        with pytest.raises(ModuleError, match="module is starting"):
            await module.get_error_string()  # everything else waits for ready
        assert not await modules_ready(caller, ["starting"])
        child.release.set()
        await asyncio.wait_for(opening, 5)
        assert await module.get_state() is ModuleState.READY
        assert await modules_ready(caller, ["starting"])
        assert not await modules_ready(caller, ["starting", "absent"])
        assert await module.get_error_string() == ""
    finally:
        child.release.set()
        await asyncio.wait_for(opening, 5)
        await starting.close()
        await caller.close()


async def test_who_and_how_a_module_is_answers_in_error_state_too() -> None:
    network = LocalNetwork()
    failing = Module(comm=LocalComm("failing", network=network), label="Failing")
    caller = Module(comm=LocalComm("caller", network=network))
    await failing.open()
    await caller.open()
    try:
        failing.set_error("the device went away")
        module = await caller.comm.proxy("failing", IModule)
        assert await module.get_state() is ModuleState.ERROR
        assert await module.get_label() == "Failing"
        assert await module.get_version() == __version__
        assert await module.get_error_string() == "the device went away"
        assert not await modules_ready(caller, ["failing"])
    finally:
        await failing.close()
        await caller.close()
