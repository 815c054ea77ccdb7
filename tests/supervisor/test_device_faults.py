"""kill -9 of an Alpaca camera module mid-exposure under ``nightcrew up`` on real Prosody and
alpaca-simulators: the supervisor restarts it, and the new process aborts the exposure the killed
one left running before it reports ready, so the next frame works."""

from __future__ import annotations

import asyncio
import importlib.util
import os
import signal
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.bridges.alpaca import AlpacaClient
from nightcrew.interfaces import ICamera, IExposureTime, IModule, ModuleState
from nightcrew.modules import Module
from nightcrew.testing import wait_for
from nightcrew.testing.alpaca import AlpacaSimulator, start_simulator

from .conftest import START_TIMEOUT, SupervisedDirectory

pytestmark = pytest.mark.xmpp


@pytest.fixture
def simulator(tmp_path: Path) -> Iterator[AlpacaSimulator]:
    if importlib.util.find_spec("alpaca_simulators") is None:
        if os.environ.get("CI") == "true":
            pytest.fail("alpaca-simulators is not installed (pip install -e .[dev])")
        pytest.skip("alpaca-simulators is not installed")
    simulator = start_simulator(tmp_path / "alpaca")
    try:
        yield simulator
    finally:
        simulator.stop()


async def _camera_state(simulator: AlpacaSimulator) -> int:
    async with AlpacaClient(simulator.url) as client:
        return int(await client.device("camera").get("camerastate"))


async def test_a_camera_module_killed_mid_exposure_comes_back_ready_to_expose(
    supervised: SupervisedDirectory, operator: Module, simulator: AlpacaSimulator, tmp_path: Path
) -> None:
    images = tmp_path / "images"
    images.mkdir()
    supervised.write_module(
        "camera",
        "nightcrew.modules.alpaca.AlpacaCamera",
        server=simulator.url,
        reconnect_interval=0.5,
        filename_pattern="/images/{DATE-OBS}.fits",
        vfs="{class: nightcrew.vfs.VirtualFileSystem, roots: {images: "
        f"{{class: nightcrew.vfs.LocalFile, root: {images}}}}}}}",
    )
    supervised.up()
    status = await supervised.wait_for_status(lambda s: s["camera"]["state"] == "running", "camera running")

    async def camera_ready() -> bool:
        if "camera" not in operator.comm.clients:
            return False
        return await (await operator.comm.proxy("camera", IModule)).get_state() is ModuleState.READY

    await wait_for(camera_ready, START_TIMEOUT, message="camera ready")
    await (await operator.comm.proxy("camera", IExposureTime)).set_exposure_time(600.0)
    exposure = asyncio.ensure_future((await operator.comm.proxy("camera", ICamera)).grab_data())
    await wait_for(lambda: _exposing(simulator), 30.0, message="the device exposing")

    first_pid = status["camera"]["pid"]
    os.kill(first_pid, signal.SIGKILL)
    await supervised.wait_for_status(
        lambda s: s["camera"]["state"] == "running" and s["camera"]["pid"] not in (None, first_pid),
        "camera restarted",
    )
    await wait_for(camera_ready, START_TIMEOUT, message="camera ready again")
    assert await _camera_state(simulator) == 0  # aborted before it said ready
    exposure.cancel()  # the call to the killed process would only end at its timeout

    await (await operator.comm.proxy("camera", IExposureTime)).set_exposure_time(0.2)
    filename = await (await operator.comm.proxy("camera", ICamera)).grab_data()
    assert (images / Path(filename).name).is_file()
    assert "still exposing (CameraState 2): abortexposure" in (supervised.log_dir / "camera.log").read_text()


async def _exposing(simulator: AlpacaSimulator) -> bool:
    return await _camera_state(simulator) == 2
