"""indiserver with the indi-bin simulators, each server in a private network namespace.

``indi_server`` is shared by the whole session (tests leave it running and its devices usable);
``own_indi_server`` gives a test a server of its own to kill and restart. Without indi-bin or root
the tests skip, except under CI=true, where they fail.
"""

from __future__ import annotations

import os
from collections.abc import AsyncIterator, Callable, Iterator
from pathlib import Path

import pytest

from nightcrew.testing.indi import SIMULATORS, IndiServer, indi_missing
from tests.indi.served import Served, serve


def _require_indi() -> None:
    missing = indi_missing()
    if not missing:
        return
    message = f"INDI tests need: {', '.join(missing)} (make system-deps installs indi-bin)"
    if os.environ.get("CI") == "true":
        pytest.fail(message)
    pytest.skip(message)


@pytest.fixture(scope="session")
def indi_server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[IndiServer]:
    """All seven simulators behind one indiserver for the whole session."""
    _require_indi()
    server = IndiServer(SIMULATORS, log_dir=tmp_path_factory.mktemp("indiserver"))
    try:
        server.start()
        yield server
    finally:
        server.stop()


@pytest.fixture
def own_indi_server(tmp_path: Path) -> Iterator[Callable[..., IndiServer]]:
    """Makes started servers for one test (``own_indi_server("indi_simulator_focus")``)."""
    _require_indi()
    servers: list[IndiServer] = []

    def make(*drivers: str) -> IndiServer:
        server = IndiServer(drivers or SIMULATORS, log_dir=tmp_path / f"indiserver{len(servers)}")
        servers.append(server)
        server.start()
        return server

    try:
        yield make
    finally:
        for server in servers:
            server.stop()


@pytest.fixture
async def served() -> AsyncIterator[Served]:
    """The simulated observatory served by IndiServer (see tests/indi/served.py)."""
    async with serve() as result:
        yield result
