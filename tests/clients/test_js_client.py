"""The JavaScript client generated from the catalogue, against the simulated observatory on Prosody.

The telescope and the camera of ``examples/sim-processes`` run as ``nightcrew run`` processes on the
session's Prosody; ``clients/js/test/observe.mjs`` (generated API only) finds them by their
interfaces, points, takes an image and receives its NewImageEvent, then tries bad input.
"""

from __future__ import annotations

import json
import os
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from nightcrew.cli.catalogue import catalogue_text
from nightcrew.cli.catalogue_js import js_client_files

# The session's Prosody and a room per test, as tests/comm has them (imported to be found here).
from tests.comm.conftest import Network, prosody_network, prosody_server  # noqa: F401
from tests.comm.xmpp_servers import DOMAIN, PASSWORD, require_command
from tests.modules.test_sim_xmpp import CLOCK_SPEED, CLOCK_START, Processes

REPOSITORY = Path(__file__).resolve().parents[2]
CLIENT = REPOSITORY / "clients" / "js"
MODULES = ["telescope", "camera"]
#: Wall seconds for logins, the modules to become ready, and the image (the camera loads stars).
TIMEOUT = 90


def test_generated_files_are_current() -> None:
    # CI fails here when the catalogue changed without `make catalogue`.
    expected = js_client_files(json.loads(catalogue_text()))
    on_disk = {p.relative_to(CLIENT / "generated").as_posix() for p in (CLIENT / "generated").rglob("*.js")}
    assert on_disk == set(expected), "clients/js/generated is stale: run `make catalogue`"
    for relative, text in expected.items():
        assert (CLIENT / "generated" / relative).read_text(encoding="utf-8") == text, (
            f"clients/js/generated/{relative} is stale: run `make catalogue`"
        )


def node_ready() -> None:
    require_command("node", "nodejs")
    if not (CLIENT / "node_modules" / "@xmpp" / "client").is_dir():
        message = "clients/js/node_modules is missing: run `make js-deps`"
        if os.environ.get("CI") == "true":
            pytest.fail(message)
        pytest.skip(message)


@pytest.fixture
def observatory(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[dict[str, Any]]:
    """Telescope and camera processes in the test's room; what the JS client needs to join it."""
    network: Network = request.getfixturevalue("prosody_network")
    server = network.server
    assert server is not None and server.ca_file is not None
    for name in [*MODULES, "jsclient"]:
        server.account(name)
    env = {
        **os.environ,
        "SIM_XMPP_PASSWORD": PASSWORD,
        "SIM_XMPP_SERVER": server.address,
        "SIM_XMPP_DOMAIN": DOMAIN,
        "SIM_XMPP_ROOM": network.room,
        "SIM_XMPP_CA_FILE": server.ca_file,
        "SIM_CLOCK_START": CLOCK_START,
        "SIM_CLOCK_SPEED": str(CLOCK_SPEED),
        "SIM_IMAGES": str(tmp_path / "images"),
    }
    processes = Processes(tmp_path)
    try:
        for name in MODULES:
            processes.start(name, env)
        yield {
            "jid": f"jsclient@{DOMAIN}",
            "password": PASSWORD,
            "server": server.address,
            "room": network.room,
            "modules": MODULES,
            "timeout": TIMEOUT,
            "ca_file": server.ca_file,
            "images": tmp_path / "images",
        }
        problems = processes.stop()
    finally:
        processes.kill()
    assert not problems, "\n".join(problems)


def run_observe(observatory: dict[str, Any]) -> dict[str, Any]:
    options = {key: observatory[key] for key in ("jid", "password", "server", "room", "modules", "timeout")}
    done = subprocess.run(
        ["node", str(CLIENT / "test" / "observe.mjs"), json.dumps(options)],
        env={**os.environ, "NODE_EXTRA_CA_CERTS": observatory["ca_file"]},
        capture_output=True,
        text=True,
        timeout=3 * TIMEOUT,
        check=False,
    )
    assert done.returncode == 0, f"observe.mjs exited {done.returncode}:\n{done.stderr}"
    report: dict[str, Any] = json.loads(done.stdout)
    return report


@pytest.mark.xmpp
def test_generated_client_observes_with_the_simulated_observatory(observatory: dict[str, Any]) -> None:
    node_ready()
    report = run_observe(observatory)

    assert {"ITelescope", "IPointingRaDec", "IModule"} <= set(report["modules"]["telescope"])
    assert {"ICamera", "IData", "IExposureTime"} <= set(report["modules"]["camera"])
    assert report["clock"]["speed"] == CLOCK_SPEED
    assert report["radec"] == pytest.approx([322.95, 48.43])
    filename = report["filename"]
    assert filename.startswith("/images/") and filename.endswith(".fits")
    assert (observatory["images"] / filename.removeprefix("/images/")).is_file()
    assert report["event"] == {
        "class": "NewImageEvent",
        "filename": filename,
        "image_type": "object",
        "sender": "camera",
    }

    bad = report["bad"]
    # Refused by the client from the catalogue's schema, before anything is sent.
    assert bad["wrong_type"] == {
        "class": "InvalidArgumentError",
        "message": "move_radec(): argument 'ra': expected number, got string \"north\"",
        "nightcrew": True,
    }
    assert bad["out_of_range"]["message"] == "move_radec(): argument 'dec': must be <= 90 (got number 95)"
    assert bad["too_many"]["message"] == "move_radec(): takes 2 arguments, got 3"
    # Refused by the telescope itself: its fault arrives as the error class it raised.
    assert bad["below_horizon"]["class"] == "MoveError"
    assert bad["unknown_module"] == {
        "class": "RemoteError",
        "message": "module 'ghost' is not online (online: camera, telescope)",
        "nightcrew": True,
    }
    assert bad["wrong_interface"]["class"] == "InterfaceError"
    assert bad["wrong_interface"]["message"].startswith("module 'camera' does not offer ITelescope (offers: ")
    assert report["warnings"] == []
