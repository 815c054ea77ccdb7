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

from nightcrew.timeout import DEFAULT_TIMEOUT

# The session's Prosody and a room per test, as tests/comm has them (imported to be found here).
from tests.comm.conftest import Network, prosody_network, prosody_server  # noqa: F401
from tests.comm.xmpp_servers import DOMAIN, PASSWORD
from tests.modules.sim_processes import CLOCK_SPEED, Processes, overlay_environment

from .node import CLIENT, node_ready

MODULES = ["telescope", "camera"]
#: Wall seconds for logins, the modules to become ready, and the image (the camera loads stars).
TIMEOUT = 90
#: Clock seconds of the exposure: longer than the default timeout window of a call, in wall time.
EXPOSURE_TIME = 60.0


@pytest.fixture
def observatory(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[dict[str, Any]]:
    """Telescope and camera processes in the test's room; what the JS client needs to join it."""
    network: Network = request.getfixturevalue("prosody_network")
    server = network.server
    assert server is not None and server.ca_file is not None
    server.account("jsclient")  # a person of the test's own, with a password of its own
    env = overlay_environment(server, network.room, tmp_path, MODULES, operators=("jsclient",))
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
            "exposure_time": EXPOSURE_TIME,
            "ca_file": server.ca_file,
            "images": tmp_path / "images",
        }
        problems = processes.stop()
    finally:
        processes.kill()
    assert not problems, "\n".join(problems)


def run_observe(observatory: dict[str, Any]) -> dict[str, Any]:
    options = {
        key: observatory[key]
        for key in ("jid", "password", "server", "room", "modules", "timeout", "exposure_time")
    }
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
    print(json.dumps(report, indent=1))  # shown when the test fails
    return report


@pytest.mark.xmpp
def test_generated_client_observes_with_the_simulated_observatory(observatory: dict[str, Any]) -> None:
    node_ready()
    report = run_observe(observatory)

    assert {"ITelescope", "IPointingRaDec", "IModule"} <= set(report["modules"]["telescope"])
    assert {"ICamera", "IData", "IExposureTime"} <= set(report["modules"]["camera"])
    assert report["clock"]["speed"] == CLOCK_SPEED
    # proxy(name, ITelescope, IModule) has IModule's methods; the camera's ICamera proxy has
    # set_exposure_time (IExposureTime, which the camera also serves), used below.
    assert report["telescope_state"] == "ready" and report["camera_is_icamera"]
    assert report["radec"] == pytest.approx([322.95, 48.43])
    filename = report["filename"]
    assert filename.startswith("/images/") and filename.endswith(".fits")
    assert (observatory["images"] / filename.removeprefix("/images/")).is_file()
    # The exposure alone takes EXPOSURE_TIME / speed wall seconds, more than the default window of
    # 10 clock seconds plus 1 s grace: the call lived on the camera's announced timeout.
    assert report["grab_wall_seconds"] > DEFAULT_TIMEOUT / CLOCK_SPEED + 1.0
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
    assert bad["below_horizon"]["class"] == "MoveError" and bad["below_horizon"]["nightcrew"]
    assert "below the limit of 15" in bad["below_horizon"]["message"]
    assert bad["unknown_module"] == {
        "class": "RemoteError",
        "message": "module 'ghost' is not online (online: camera, telescope)",
        "nightcrew": True,
    }
    assert bad["wrong_interface"]["class"] == "InterfaceError"
    assert bad["wrong_interface"]["message"].startswith("module 'camera' does not offer ITelescope (offers: ")
    second = bad["wrong_second_interface"]
    assert second["class"] == "InterfaceError"
    assert second["message"].startswith("module 'camera' does not offer ITelescope (offers: ")
    assert report["wrong_password"] == {
        "class": "XmppAuthError",
        "message": f"the server refused the login of jsclient@{DOMAIN}",
        "nightcrew": True,
    }
    assert report["warnings"] == []
