"""A call refused for its arguments: one message naming the method once, and no timeout announced."""

from __future__ import annotations

import math
from typing import Any

import pytest

from nightcrew.comm.rpc import RpcServer
from nightcrew.errors import InvalidArgumentError
from nightcrew.interfaces import IPointingRaDec
from nightcrew.modules import Module

from .conftest import Network


class _Mount(Module, IPointingRaDec):
    """A mount that accepts anything the interface lets through (no checks of its own)."""

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.moved: list[tuple[float, float]] = []

    async def move_radec(self, ra: float, dec: float) -> None:
        self.moved.append((ra, dec))

    async def get_radec(self) -> tuple[float, float]:
        return self.moved[-1] if self.moved else (0.0, 0.0)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([10.0], "move_radec(): missing argument 'dec'"),
        ([], "move_radec(): missing argument 'ra'"),
        ([1.0, 2.0, 3.0], "move_radec(): takes 2 arguments, got 3"),
        (["ten", 0.0], "move_radec(): argument 'ra': expected number, got string \"ten\""),
        ([10.0, 95.0], "move_radec(): argument 'dec': 95.0 is out of range (must be <= 90.0 deg)"),
        ([360.0, 0.0], "move_radec(): argument 'ra': 360.0 is out of range (must be < 360.0 deg)"),
        ([-1.0, 0.0], "move_radec(): argument 'ra': -1.0 is out of range (must be >= 0.0 deg)"),
        # NaN is refused by the wire check every RPC argument passes, before any declared bound.
        ([math.nan, 0.0], "move_radec(): argument 'ra': NaN is not a finite number"),
    ],
)
async def test_refused_arguments_are_refused_before_any_announcement(
    args: list[object], message: str
) -> None:
    mount = _Mount(name="mount")
    server = RpcServer(mount)
    announced: list[float] = []
    with pytest.raises(InvalidArgumentError) as info:
        await server.handle("move_radec", args, announced.append)
    assert info.value.message == message
    assert announced == []  # move_radec announces 300 s, but only for a call it accepted
    assert mount.moved == []


async def test_accepted_call_is_announced_then_runs() -> None:
    mount = _Mount(name="mount")
    server = RpcServer(mount)
    announced: list[float] = []
    await server.handle("move_radec", [359.5, -90.0], announced.append)
    assert announced == [300.0]
    assert mount.moved == [(359.5, -90.0)]


async def test_missing_argument_message_across_the_network(network: Network) -> None:
    await network.start(_Mount, "mount")
    caller = await network.start(Module, "caller")
    with pytest.raises(InvalidArgumentError) as info:
        await caller.comm.execute("mount", "move_radec", [10.0])
    assert str(info.value) == "mount: move_radec(): missing argument 'dec'"
    proxy = await caller.comm.proxy("mount", IPointingRaDec)
    with pytest.raises(InvalidArgumentError, match=r"^mount: move_radec\(\): argument .dec.: 91.0 is out"):
        await proxy.move_radec(0.0, 91.0)
