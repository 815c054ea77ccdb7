"""Fixtures all test directories share: in-process observatories (nightcrew.testing) on virtual time."""

from __future__ import annotations

import faulthandler
import os
import sys
import threading
from collections.abc import AsyncIterator, Generator, Iterator
from pathlib import Path

import pytest
import yaml

from nightcrew.night.build import bundled_observatory
from nightcrew.security import starting_policy
from nightcrew.server import create_missing_passwords
from nightcrew.testing import Observatory
from nightcrew.testing.solver import running_solver
from nightcrew.vfs import MemoryFile

#: Wall seconds beyond a test's own timeout after which the run ends with every thread's stack.
#: pytest-timeout fails a test by raising inside it; a teardown stuck in an event loop that
#: swallows that exception (a task that never ends while the loop cancels its tasks) would
#: otherwise hang CI until its own limit, with no test named.
HARD_LIMIT_GRACE_S = 120.0


def _end_the_run(config: pytest.Config, nodeid: str) -> None:
    # pytest captures fd 2 during a test: give the terminal back first, or the stacks are lost.
    capture = config.pluginmanager.getplugin("capturemanager")
    if capture is not None:
        capture.suspend_global_capture(in_=False)
    sys.stderr.write(f"\n{nodeid} is still running past its timeout: every thread's stack, then exit\n")
    faulthandler.dump_traceback(file=sys.stderr, all_threads=True)
    sys.stderr.flush()
    os._exit(70)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item) -> Generator[None, None, None]:
    marker = item.get_closest_marker("timeout")
    timeout = float(marker.args[0]) if marker and marker.args else float(item.config.getini("timeout"))
    guard = threading.Timer(timeout + HARD_LIMIT_GRACE_S, _end_the_run, args=(item.config, item.nodeid))
    guard.daemon = True
    guard.start()
    try:
        yield
    finally:
        guard.cancel()


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    """On a virtual clock: a 60 s roof closing takes no wall time to speak of."""
    async with Observatory() as obs:
        yield obs


@pytest.fixture
async def fast_observatory() -> AsyncIterator[Observatory]:
    """On a virtual clock, for the automation tests (with the shared in-memory files cleared after)."""
    obs = Observatory()
    try:
        yield obs
    finally:
        await obs.close()
        MemoryFile.clear_shared()


@pytest.fixture(scope="session")
def solver_url() -> Iterator[str]:
    """The plate-solving service (``nightcrew solver``), one for the session: it starts in ~1 s."""
    with running_solver() as url:
        yield url


@pytest.fixture(scope="session")
def bundled_passwords(tmp_path_factory: pytest.TempPathFactory) -> str:
    """The bundled observatory's accounts' passwords, made once as `nightcrew server init` makes
    them (0600 in a 0700 folder): the folder, for SIM_XMPP_SECRETS."""
    folder = str(tmp_path_factory.mktemp("bundled") / "secrets")
    environ = {**os.environ, "SIM_XMPP_SECRETS": folder}
    create_missing_passwords(bundled_observatory().rglob("*.yaml"), environ=environ)
    return folder


@pytest.fixture
def bundled_xmpp_files(tmp_path: Path, bundled_passwords: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """What `nightcrew server init xmpp` would give the bundled observatory's comm (a password per
    account in SIM_XMPP_SECRETS, certificate, starting policy), so that `nightcrew check` reads its
    module files as `up` would."""
    certificate = tmp_path / "observatory.local.crt"
    certificate.write_text("a certificate\n", encoding="utf-8")
    policy = tmp_path / "access.policy"
    modules = sorted(path.stem for path in bundled_observatory().rglob("*.yaml"))
    policy.write_text(yaml.safe_dump(starting_policy(modules, {"operator": "operator"})), encoding="utf-8")
    monkeypatch.setenv("SIM_XMPP_SECRETS", bundled_passwords)
    monkeypatch.setenv("SIM_XMPP_CA_FILE", str(certificate))
    monkeypatch.setenv("SIM_XMPP_POLICY", str(policy))
