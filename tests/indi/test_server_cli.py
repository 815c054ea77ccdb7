"""``nightcrew sim --indi PORT`` serves the simulated night to INDI clients; the example config checks."""

from __future__ import annotations

import asyncio
import os
import re
import signal
import socket
import subprocess
import sys
from datetime import datetime
from pathlib import Path

import pytest

from nightcrew.astro import altaz_to_radec, j2000_to_of_date
from nightcrew.server import create_missing_passwords
from tests.indi.server_clients import PATIENCE, getprop, require_clients, setprop, wait_for
from tests.modules.sim_processes import secrets_folder, starting_policy_file

REPOSITORY = Path(__file__).resolve().parents[2]
NIGHTCREW = [sys.executable, "-m", "nightcrew"]


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


async def test_sim_serves_its_devices_over_indi_while_the_night_runs(tmp_path: Path) -> None:
    require_clients()
    port = free_port()
    night = await asyncio.create_subprocess_exec(
        *NIGHTCREW,
        "sim",
        "--quick",
        "--targets=1",
        "--filters=V",
        "--exposure-time=5",
        "--calibration-frames=0",
        # The night's work ends 19 clock minutes after its start (15 of them waiting for the
        # weather to be good long enough); 36 minutes instead of --quick's hour leave a wide margin
        # at the accelerated clock's 60x.
        "--hours=0.6",
        f"--indi={port}",
        f"--out={tmp_path / 'night'}",
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    specs = [
        "telescope.EQUATORIAL_EOD_COORD.RA",
        "telescope.EQUATORIAL_EOD_COORD.DEC",
        "camera.DRIVER_INFO.DRIVER_INTERFACE",
        "roof.DOME_SHUTTER.SHUTTER_OPEN",
        "filters.FILTER_NAME.FILTER_SLOT_NAME_1",
    ]
    try:
        loop = asyncio.get_running_loop()
        deadline = loop.time() + PATIENCE
        values: dict[str, str] = {}
        while night.returncode is None and loop.time() < deadline and not all(s in values for s in specs):
            values = await getprop(str(port), *specs)
        assert all(s in values for s in specs), f"not served while the night ran: {values}"
        assert 0.0 <= float(values["telescope.EQUATORIAL_EOD_COORD.RA"]) < 24.0
        assert values["camera.DRIVER_INFO.DRIVER_INTERFACE"] == "2"
        out, err = await asyncio.wait_for(night.communicate(), 10 * PATIENCE)
    finally:
        if night.returncode is None:
            night.kill()
            await night.wait()
    assert night.returncode == 0, err.decode()[-2000:]
    # One science frame; the focus series before it wrote frames too, which are not announced.
    assert re.search(
        rb"night complete: \d+ frames \(1 science and calibration, \d+ focus and acquisition\)", out
    )


async def test_an_indi_client_takes_the_observatory_from_the_robotic_night(tmp_path: Path) -> None:
    """docs/indi.md, "Who drives": a client's first request stops the robotic mode, which parks
    first; then the client's unpark and slew stand (nobody parks the telescope again)."""
    require_clients()
    port = str(free_port())
    night = await asyncio.create_subprocess_exec(
        *NIGHTCREW,
        "sim",
        "--quick",
        "--targets=1",
        "--filters=V",
        "--calibration-frames=0",
        "--hours=0.5",
        f"--indi={port}",
        f"--out={tmp_path / 'night'}",
        stdout=asyncio.subprocess.PIPE,
        stderr=asyncio.subprocess.PIPE,
    )
    try:
        where = [
            "telescope.TIME_UTC.UTC",
            "telescope.GEOGRAPHIC_COORD.LAT",
            "telescope.GEOGRAPHIC_COORD.LONG",
        ]
        await wait_for(port, where, lambda v: True)
        await setprop(port, "telescope.TELESCOPE_PARK.UNPARK=On")
        unparked = {"telescope.TELESCOPE_PARK.UNPARK": "On", "telescope.TELESCOPE_PARK._STATE": "Ok"}
        await wait_for(port, list(unparked), lambda v: all(v[k] == want for k, want in unparked.items()))
        # 70 degrees high in the south at the server's time (TIME_UTC), in INDI's JNow.
        values = await getprop(port, *where)
        moment = datetime.fromisoformat(values["telescope.TIME_UTC.UTC"] + "+00:00").timestamp()
        latitude, longitude = (float(values[k]) for k in where[1:])
        ra, dec = j2000_to_of_date(*altaz_to_radec(70.0, 180.0, latitude, longitude, moment), moment)
        await setprop(port, f"telescope.EQUATORIAL_EOD_COORD.RA;DEC={ra / 15.0};{dec}")
        arrived = ["telescope.EQUATORIAL_EOD_COORD.DEC", "telescope.EQUATORIAL_EOD_COORD._STATE"]
        await wait_for(
            port,
            [*arrived, "telescope.TELESCOPE_PARK.PARK"],
            lambda v: (
                abs(float(v[arrived[0]]) - dec) < 0.1
                and v[arrived[1]] == "Ok"
                and v["telescope.TELESCOPE_PARK.PARK"] == "Off"
            ),
        )
        night.send_signal(signal.SIGINT)  # Ctrl-C: the night ends at once, parked and closed
        _, err = await asyncio.wait_for(night.communicate(), 10 * PATIENCE)
    finally:
        if night.returncode is None:
            night.kill()
            await night.wait()
    assert night.returncode == 130, err.decode()[-2000:]  # ended by Ctrl-C, as asked


def test_sim_refuses_a_port_that_is_no_port() -> None:
    result = subprocess.run(
        [*NIGHTCREW, "sim", "--quick", "--indi=70000"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == 2
    assert "--indi: not a port number (0..65535): 70000" in result.stderr


def test_the_example_server_config_checks(tmp_path: Path) -> None:
    # Its password, certificate and policy are what `nightcrew server init` makes.
    certificate = tmp_path / "observatory.local.crt"
    certificate.write_text("a certificate\n", encoding="utf-8")
    policy = starting_policy_file(tmp_path, "observatory.local")
    env = {**os.environ, "SIM_XMPP_SECRETS": secrets_folder(tmp_path), "SIM_XMPP_CA_FILE": str(certificate)}
    env["SIM_XMPP_POLICY"] = policy
    path = REPOSITORY / "examples" / "indi" / "server.yaml"
    create_missing_passwords([path], environ=env)
    result = subprocess.run(
        [*NIGHTCREW, "check", str(path)], capture_output=True, text=True, env=env, timeout=120, check=False
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == f"OK {path}"


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"port": 70000}, "key 'port': must be a TCP port 0..65535, got 70000"),
        ({"poll_interval": 0}, "key 'poll_interval': must be > 0 seconds, got 0"),
        (
            {"telescope": None, "camera": None, "focuser": None, "filters": None, "dome": None},
            "nothing to serve",
        ),
        ({"dome": "telescope"}, "key 'dome': module 'telescope' is already served as another device"),
        ({"pixel_size": 200}, "key 'pixel_size': must be 0 .. 100 µm, got 200"),
        ({"robotic": " "}, "key 'robotic': must be a module name, got ' '"),
        ({"handover_timeout": 0}, "key 'handover_timeout': must be 1 .. 3600 seconds, got 0"),
    ],
)
def test_bad_server_options_are_named(change: dict[str, object], message: str) -> None:
    from nightcrew.errors import ConfigError
    from nightcrew.modules.indi.server import IndiServer

    options: dict[str, object] = {"name": "indi", "telescope": "telescope", "dome": "roof", **change}
    with pytest.raises(ConfigError, match=message):
        IndiServer(**options)  # type: ignore[arg-type]
