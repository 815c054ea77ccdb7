"""The simulators (and the server) an observatory directory is written for in these tests.

alpaca-simulators runs from the config ``nightcrew alpaca simulator DIR`` writes (the offline star
table included), so its devices, numbers and names are the ones a user meets. Without it installed
the tests skip, except under CI=true, where they fail.
"""

from __future__ import annotations

import importlib.util
import os
from collections.abc import Iterable, Iterator
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.testing.alpaca import AlpacaSimulator
from nightcrew.testing.indi import SIMULATORS, IndiServer, indi_missing
from nightcrew.testing.processes import free_port
from tests.comm.xmpp_servers import require_command

__all__ = ["require_simulators", "run_alpaca_simulators", "run_indi_simulators", "server_init"]


def require_simulators() -> None:
    if importlib.util.find_spec("alpaca_simulators") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("alpaca-simulators is not installed (pip install -e .[dev])")
        pytest.skip("alpaca-simulators is not installed")


def run_alpaca_simulators(
    directory: Path, *, latitude: float = 48.0, longitude: float = 8.0
) -> Iterator[AlpacaSimulator]:
    """alpaca-simulators on a free loopback port, configured by ``nightcrew alpaca simulator``."""
    require_simulators()
    args = ["alpaca", "simulator", str(directory), "--latitude", str(latitude), "--longitude", str(longitude)]
    assert main(args) == 0
    simulator = AlpacaSimulator(directory=directory, port=free_port(), config_path=directory / "config.yaml")
    simulator.start()
    try:
        yield simulator
    finally:
        simulator.stop()


def server_init(directory: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """``nightcrew server init xmpp *.yaml`` in ``directory``, as the guide does (accounts and the
    certificate the comm names; the server is not started). Skips without Prosody, but not on CI."""
    require_command("prosody", "prosody")
    monkeypatch.chdir(directory)
    assert main(["server", "init", "xmpp", *sorted(p.name for p in directory.glob("*.yaml"))]) == 0


def run_indi_simulators(log_dir: Path, drivers: Iterable[str] = SIMULATORS) -> Iterator[IndiServer]:
    """indiserver with every indi-bin simulator in a network namespace of its own (reached at
    ``server.host:server.port`` like a remote server), or with ``drivers`` only. Skips without
    indi-bin or root, not on CI."""
    missing = indi_missing()
    if missing:
        message = f"INDI tests need: {', '.join(missing)} (make system-deps installs indi-bin)"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)
    server = IndiServer(drivers, log_dir=log_dir)
    try:
        server.start()
        yield server
    finally:
        server.stop()
