"""alpaca-simulators (the real third-party Alpaca server) for the Alpaca tests.

``alpaca_simulator`` is one server for the whole session (state carries over between tests: start
from what you set, not from the template's values); ``start_alpaca_simulator`` starts a private one
(e.g. to kill and restart it). Both serve stars from the offline table built once per session.
Without alpaca-simulators installed the tests skip, except under CI=true, where they fail.
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import AsyncIterator, Callable, Iterator
from pathlib import Path
from typing import Any

import pytest

from nightcrew.testing.alpaca import AlpacaSimulator, build_star_table, start_simulator

from .faulty_server import FaultyServer


def _require_simulators() -> None:
    if importlib.util.find_spec("alpaca_simulators") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("alpaca-simulators is not installed (pip install -e .[dev])")
        pytest.skip("alpaca-simulators is not installed")


@pytest.fixture(scope="session")
def alpaca_star_table(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The offline Gaia table alpaca-simulators' camera reads (built once per session)."""
    _require_simulators()
    return build_star_table(tmp_path_factory.mktemp("alpaca-stars") / "gaia_sources.db")


@pytest.fixture(scope="session")
def alpaca_simulator(
    tmp_path_factory: pytest.TempPathFactory, alpaca_star_table: Path
) -> Iterator[AlpacaSimulator]:
    """One alpaca-simulators server on 127.0.0.1 for the session."""
    simulator = start_simulator(tmp_path_factory.mktemp("alpaca-simulators"), star_table=alpaca_star_table)
    try:
        yield simulator
    finally:
        simulator.stop()


@pytest.fixture(scope="session")
def more_devices_url(tmp_path_factory: pytest.TempPathFactory, alpaca_star_table: Path) -> Iterator[str]:
    """A private simulator whose cover-calibrators have a light (the default one's has none), with
    a dome and a flat panel (:mod:`.more_devices`); one for the session."""
    from .more_devices import start_with_more_devices

    with start_with_more_devices(tmp_path_factory.mktemp("alpaca-more"), alpaca_star_table) as simulator:
        yield simulator.url


@pytest.fixture
def start_alpaca_simulator(
    tmp_path: Path, alpaca_star_table: Path
) -> Iterator[Callable[..., AlpacaSimulator]]:
    """Start private alpaca-simulators servers (``overrides`` as in start_simulator); stopped after."""
    started: list[AlpacaSimulator] = []

    def start(**kwargs: Any) -> AlpacaSimulator:
        simulator = start_simulator(
            tmp_path / f"alpaca-{len(started)}", star_table=alpaca_star_table, **kwargs
        )
        started.append(simulator)
        return simulator

    try:
        yield start
    finally:
        for simulator in started:
            simulator.stop(grace=1.0)  # a private server: nothing of it is kept


@pytest.fixture
async def faulty() -> AsyncIterator[FaultyServer]:
    """A misbehaving Alpaca server on 127.0.0.1: each test sets its replies (``true`` otherwise)."""
    server = FaultyServer()
    await server.start()
    try:
        yield server
    finally:
        await server.stop()
