"""``nightcrew up examples/sim-processes``: the simulated observatory as supervised processes on Prosody.

The directory is a copy of the repository's ``examples/observatory`` and ``examples/sim-processes``
whose weather station's overlay plays a rainy scenario, as a user changes a file: the weather
verdict must then send a BadWeatherEvent (issue 29: no weather event was ever sent).
"""

from __future__ import annotations

import asyncio
import os
import shutil
import signal
import subprocess
import sys
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from nightcrew.comm.xmpp import XmppComm
from nightcrew.events import BadWeatherEvent, Event
from nightcrew.modules import Module
from nightcrew.testing import modules_ready, wait_for
from tests.comm.xmpp_servers import DOMAIN, PASSWORD
from tests.modules.sim_processes import overlay_passwords, secrets_folder, starting_policy_file

from .conftest import REPOSITORY, START_TIMEOUT, Prosody

pytestmark = pytest.mark.xmpp
DEVICES = {"camera", "filters", "focuser", "roof", "telescope", "conditions", "watchdog"}
#: examples/observatory/robotic, each a process too (test_observatory_up.py gives them a task).
ROBOTIC = {"weather", "scheduler", "mastermind", "focus", "flatfield", "flatpointing", "acquisition"}
ROBOTIC |= {"guiding", "seeing", "recorder"}
MODULES = DEVICES | ROBOTIC
#: Rain from the start (a key in the overlay wins over the bundled file's): the verdict's first look
#: finds it bad and says so at once.
RAIN = "scenario: [{at: 0, rain: true, humidity: 97}]\n"


def rainy_copy(tmp_path: Path) -> Path:
    """``examples/sim-processes`` beside ``examples/observatory`` in ``tmp_path``, the station raining."""
    for name in ("observatory", "sim-processes"):
        ignore = shutil.ignore_patterns("frames", "xmpp", "secrets", "logs", "*.sqlite*", "*.jsonl")
        shutil.copytree(REPOSITORY / "examples" / name, tmp_path / "examples" / name, ignore=ignore)
    overlay = tmp_path / "examples" / "sim-processes" / "conditions.yaml"
    overlay.write_text(overlay.read_text(encoding="utf-8") + RAIN, encoding="utf-8")
    return overlay.parent


@pytest.fixture
async def operator(prosody: Prosody, tmp_path: Path) -> AsyncIterator[Module]:
    prosody.account("operator")
    comm = XmppComm(  # as operator.yaml: naming the observatory's policy, which trusts the verdict
        f"operator@{DOMAIN}",
        PASSWORD,
        server=prosody.address,
        room="simproc",
        ca_file=str(prosody.ca_file),
        policy=starting_policy_file(tmp_path, DOMAIN),
    )
    module = Module(comm=comm)
    await module.open()
    try:
        yield module
    finally:
        await module.close()


async def nightcrew(*args: str, env: dict[str, str]) -> tuple[int, str]:
    process = await asyncio.create_subprocess_exec(
        sys.executable, "-m", "nightcrew", *args, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT
    )
    output, _ = await asyncio.wait_for(process.communicate(), 60)
    assert process.returncode is not None
    return process.returncode, output.decode()


async def test_up_runs_the_simulated_observatory(prosody: Prosody, operator: Module, tmp_path: Path) -> None:
    passwords = overlay_passwords(tmp_path, DOMAIN)  # as `server init` makes them
    for name in MODULES:
        prosody.account(name, passwords[name])
    example = rainy_copy(tmp_path)
    bad_weather: list[str] = []

    async def on_bad_weather(event: Event, sender: str) -> None:
        bad_weather.append(sender)

    await operator.comm.register_event(BadWeatherEvent, on_bad_weather)
    socket = Path(os.environ.get("TMPDIR", "/tmp")) / f"nc-sim-{os.getpid()}.sock"
    env = {
        **os.environ,
        "SIM_XMPP_SECRETS": secrets_folder(tmp_path),
        "SIM_XMPP_SERVER": prosody.address,
        "SIM_XMPP_DOMAIN": DOMAIN,
        "SIM_XMPP_ROOM": "simproc",
        "SIM_XMPP_CA_FILE": str(prosody.ca_file),
        "SIM_XMPP_POLICY": starting_policy_file(tmp_path, DOMAIN),
        "SIM_IMAGES": str(tmp_path / "images"),
        "OBSERVATORY_DATA": str(tmp_path / "data"),
        "NIGHTCREW_SUPERVISOR_SOCKET": str(socket),
    }
    log = tmp_path / "supervisor.log"
    stderr = os.open(log, os.O_WRONLY | os.O_CREAT, 0o600)
    try:
        up = await asyncio.create_subprocess_exec(
            sys.executable, "-m", "nightcrew", "up", str(example), "--log-dir", str(tmp_path / "logs"),
            env=env, cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=stderr,
        )  # fmt: skip
    finally:
        os.close(stderr)
    try:
        await wait_for(
            lambda: modules_ready(operator, MODULES), START_TIMEOUT * 2, message="all modules ready"
        )
        code, shown = await nightcrew("status", env=env)
        assert code == 0, shown
        rows = {line.split()[0]: line.split() for line in shown.splitlines()[1:]}
        assert set(rows) == MODULES  # operator.yaml is not a module; xmpp.yaml and clock.yaml are fragments
        assert all(row[1] == "running" for row in rows.values())

        os.kill(int(rows["filters"][2]), signal.SIGKILL)
        await wait_for(lambda: "filters" not in operator.comm.clients, 30, message="filters gone")
        await wait_for(lambda: modules_ready(operator, ["filters"]), START_TIMEOUT, message="filters back")
        code, shown = await nightcrew("status", "filters", env=env)
        row = shown.splitlines()[1].split()
        assert (row[0], row[1], row[3]) == ("filters", "running", "1"), shown
        assert row[2] != rows["filters"][2] and shown.rstrip().endswith("killed by SIGKILL"), shown

        code, logs = await nightcrew("logs", "weather", "-n", "200", env=env)
        assert code == 0 and "weather is ready" in logs
        # The verdict looks every 30 clock s (3 wall s at the overlays' speed 10).
        await wait_for(lambda: bad_weather == ["weather"], 30, message="BadWeatherEvent from the verdict")
    finally:
        if up.returncode is None:
            up.send_signal(signal.SIGTERM)
        await asyncio.wait_for(up.wait(), 90)
    assert up.returncode == 0, log.read_text()
    await wait_for(lambda: not set(operator.comm.clients) & MODULES, 30, message="all modules left")
