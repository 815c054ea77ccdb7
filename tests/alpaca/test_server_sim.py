"""``nightcrew sim --alpaca PORT``: the bundled simulated observatory served to Alpaca clients.

The command runs as a user runs it (a subprocess), on loopback with free ports; alpyca finds it by
discovery, opens the roof, slews, takes an image, and SIGTERM (to the PID we started) stops it
cleanly after parking.
"""

from __future__ import annotations

import asyncio
import os
import re
import shutil
import signal
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import pytest
from alpaca.camera import Camera  # type: ignore[import-untyped]
from alpaca.covercalibrator import CoverCalibrator  # type: ignore[import-untyped]
from alpaca.dome import Dome, ShutterState  # type: ignore[import-untyped]
from alpaca.rotator import Rotator  # type: ignore[import-untyped]
from alpaca.switch import Switch  # type: ignore[import-untyped]
from alpaca.telescope import Telescope  # type: ignore[import-untyped]

from alpaca import management  # type: ignore[import-untyped]
from nightcrew.bridges.alpaca.discovery import DiscoveredServer, discover_servers
from nightcrew.night.build import bundled_observatory

from .served import wait_in_thread

_BANNER = re.compile(r"at http://127\.0\.0\.1:(\d+) \(discovery on UDP port (\d+)\)")


@contextmanager
def _running_sim(tmp_path: Path, *options: str) -> Iterator[tuple[subprocess.Popen[str], int, int]]:
    command = [sys.executable, "-m", "nightcrew", "sim", "--alpaca", "0", "--alpaca-discovery-port", "0"]
    # 30x real time: the roof opens in 2 s, the 2-s readout takes a tenth of that.
    command += ["--speed", "30", "--out", str(tmp_path / "out"), *options]
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True
    )
    try:
        assert process.stdout is not None
        banner = process.stdout.readline()  # ends when the server is up, or when the process dies
        match = _BANNER.search(banner)
        assert match, f"no banner: {banner!r}; stderr: {process.stderr.read() if process.stderr else ''}"
        yield process, int(match.group(1)), int(match.group(2))
    finally:
        if process.poll() is None:
            os.kill(process.pid, signal.SIGKILL)
        process.wait(timeout=30)


@pytest.fixture
def sim_server(tmp_path: Path) -> Iterator[tuple[subprocess.Popen[str], int, int]]:
    with _running_sim(tmp_path) as running:
        yield running


async def test_sim_serves_its_devices_to_alpyca(sim_server: tuple[subprocess.Popen[str], int, int]) -> None:
    process, port, discovery_port = sim_server
    found = await discover_servers("127.255.255.255", port=discovery_port, wait=0.5)
    assert DiscoveredServer("127.0.0.1", port) in found
    address = f"127.0.0.1:{port}"
    devices = await asyncio.to_thread(management.configureddevices, address)
    assert {(d["DeviceType"], d["DeviceName"]) for d in devices} == {
        ("Telescope", "telescope"),
        ("Camera", "camera"),
        ("Dome", "roof"),
        ("Focuser", "focuser"),
        ("FilterWheel", "filters"),
        ("SafetyMonitor", "weather"),
        ("ObservingConditions", "conditions"),
    }

    dome, telescope, camera = Dome(address, 0), Telescope(address, 0), Camera(address, 0)
    for device in (dome, telescope, camera):
        await asyncio.to_thread(setattr, device, "Connected", True)
    await asyncio.to_thread(dome.OpenShutter)
    await asyncio.to_thread(telescope.Unpark)
    await wait_in_thread(lambda: dome.ShutterStatus == ShutterState.shutterOpen, 60.0, "roof open")
    await wait_in_thread(lambda: not telescope.AtPark and not telescope.Slewing, 60.0, "unparked")
    await asyncio.to_thread(telescope.SlewToAltAzAsync, 180.0, 60.0)
    await wait_in_thread(lambda: not telescope.Slewing, 60.0, "slewed")

    await asyncio.to_thread(camera.StartExposure, 1.0, True)
    await wait_in_thread(lambda: camera.ImageReady, 120.0, "image ready")
    raw = await asyncio.to_thread(lambda: camera.ImageArrayRaw)
    info = await asyncio.to_thread(lambda: camera.ImageArrayInfo)
    assert (info.Dimension1, info.Dimension2) == (2048, 2048)
    assert await asyncio.to_thread(lambda: camera.PixelSizeX) == 9.0  # from camera.yaml
    assert np.array(raw, dtype=np.uint16).std() > 0

    os.kill(process.pid, signal.SIGTERM)
    _, err = await asyncio.to_thread(process.communicate, None, 60)
    assert process.returncode == 0, err
    assert "stopping: parking the telescope and closing the roof" in err
    assert "could not" not in err  # park_and_close logs failures as "could not ..."


_MORE_MODULES = {
    "rotator.yaml": "class: nightcrew.modules.sim.SimRotator\nspeed: 30.0\n",
    "switch.yaml": "class: nightcrew.modules.sim.SimSwitch\nswitches: [{name: dew heater, max_value: 100}]\n",
    "flatpanel.yaml": "class: nightcrew.modules.sim.SimCoverCalibrator\n",
}


async def test_sim_serves_rotators_switches_and_flat_panels_of_its_configs(tmp_path: Path) -> None:
    configs = tmp_path / "observatory"
    shutil.copytree(bundled_observatory(), configs)
    for name, text in _MORE_MODULES.items():
        (configs / name).write_text(text)
    with _running_sim(tmp_path, "--configs", str(configs)) as (process, port, _):
        address = f"127.0.0.1:{port}"
        devices = await asyncio.to_thread(management.configureddevices, address)
        served = {(d["DeviceType"], d["DeviceName"]) for d in devices}
        assert {("Rotator", "rotator"), ("Switch", "switch"), ("CoverCalibrator", "flatpanel")} <= served
        rotator, switch, panel = Rotator(address, 0), Switch(address, 0), CoverCalibrator(address, 0)
        for device in (rotator, switch, panel):
            await asyncio.to_thread(setattr, device, "Connected", True)
        await asyncio.to_thread(rotator.MoveAbsolute, 45.0)
        await wait_in_thread(lambda: not rotator.IsMoving, 60.0, "rotated")
        assert await asyncio.to_thread(lambda: rotator.Position) == 45.0
        await asyncio.to_thread(switch.SetSwitchValue, 0, 25.0)
        assert await asyncio.to_thread(switch.GetSwitchValue, 0) == 25.0
        assert await asyncio.to_thread(lambda: panel.MaxBrightness) > 0
        os.kill(process.pid, signal.SIGTERM)
        _, err = await asyncio.to_thread(process.communicate, None, 60)
        assert process.returncode == 0, err
