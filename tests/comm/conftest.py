"""The network fixture: every contract test runs once per transport."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any, TypeVar

import pytest

from nightcrew.comm.base import Comm
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.modules import Module

M = TypeVar("M", bound=Module)


class Network:
    """Builds modules on one transport and closes them after the test."""

    def __init__(self, kind: str) -> None:
        self.kind = kind
        self._local = LocalNetwork()
        self._modules: list[Module] = []

    def comm(self, name: str) -> Comm:
        return LocalComm(name, network=self._local)

    async def start(self, cls: type[M], name: str, **kwargs: Any) -> M:
        module = cls(comm=self.comm(name), **kwargs)
        self._modules.append(module)
        await module.open()
        return module

    async def close(self) -> None:
        for module in reversed(self._modules):
            await module.close()


@pytest.fixture(params=["local"])
async def network(request: pytest.FixtureRequest) -> AsyncIterator[Network]:
    net = Network(request.param)
    try:
        yield net
    finally:
        await net.close()
