"""AlpacaCamera beyond the contract: pixels as the device sent them, gain, readout modes, cooling,
and faults (Alpaca error, wrong image size, JSON fallback, timeout) with no file written."""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Any

import numpy as np
import pytest

from nightcrew.bridges.alpaca import imagebytes
from nightcrew.clock import RealClock
from nightcrew.errors import GrabImageError, InvalidArgumentError
from nightcrew.interfaces import ModuleState
from nightcrew.modules.alpaca import AlpacaCamera
from nightcrew.testing import Observatory
from nightcrew.testing.alpaca import SIMULATOR_SITE, AlpacaSimulator
from tests.alpaca.faulty_server import FaultyServer, alpaca_error, image_bytes, json_image, value


async def test_the_fits_file_holds_the_devices_pixels_rows_first(alpaca_simulator: AlpacaSimulator) -> None:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        camera = await obs.start(AlpacaCamera, "camera", server=alpaca_simulator.url)
        await camera.set_binning(2, 2)
        await camera.set_window(0, 0, 512, 256)  # wider than high: a transposed image would show
        await camera.set_exposure_time(0.2)
        filename = await camera.grab_data()
        hdu = (await obs.vfs.read_fits(filename))[0]
        assert hdu.data.shape == (128, 256)
        # alpaca-simulators keeps the last frame: the same pixels, straight from the device
        np.testing.assert_array_equal(hdu.data, await camera.device.image_array())
        assert hdu.header["CCD-TEMP"] == pytest.approx(await camera.device.get("ccdtemperature"))
        assert (await camera.device.get("binx"), await camera.device.get("numx")) == (2, 256)


async def test_gain_readout_mode_and_cooling(alpaca_simulator: AlpacaSimulator) -> None:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        camera = await obs.start(AlpacaCamera, "camera", server=alpaca_simulator.url)
        assert await camera.get_config_value_options("readout_mode") == ["Fast", "Normal", "High Quality"]
        await camera.set_config_value("readout_mode", "High Quality")
        assert await camera.get_config_value("readout_mode") == "High Quality"
        assert await camera.device.get("readoutmode") == 2
        with pytest.raises(InvalidArgumentError, match="unknown readout mode 'Turbo'"):
            await camera.set_config_value("readout_mode", "Turbo")
        await camera.set_gain(3)
        assert await camera.device.get("gain") != 1  # the device took it (its read-back is its own)
        with pytest.raises(InvalidArgumentError, match="gain must be an index"):
            await camera.set_gain(42)
        await camera.set_cooling(True, -15.0)
        assert await camera.device.get("cooleron") is True
        assert await camera.device.get("setccdtemperature") == pytest.approx(-15.0)
        status = await camera.get_cooling()
        assert status.enabled and status.setpoint == -15.0
        await camera.set_cooling(False, -15.0)
        assert await camera.device.get("cooleron") is False


async def test_exposure_times_beyond_the_devices_maximum_are_refused(
    alpaca_simulator: AlpacaSimulator,
) -> None:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        # Configured above what the device can do: the device's ExposureMax is the limit.
        camera = await obs.start(AlpacaCamera, "camera", server=alpaca_simulator.url, max_exposure_time=7200)
        device_max = await camera.device.get("exposuremax")
        assert device_max < 7200
        await camera.set_exposure_time(device_max)
        with pytest.raises(
            InvalidArgumentError, match=r"out of range for camera: .*\(the maximum is the device's"
        ):
            await camera.set_exposure_time(device_max + 1)
        assert await camera.get_exposure_time() == device_max


CAMERA_MEMBERS: dict[str, Any] = {
    "cameraxsize": 8,
    "cameraysize": 4,
    "maxbinx": 1,
    "maxbiny": 1,
    "canasymmetricbin": False,
    "gains": [],
    "readoutmodes": [],
    "camerastate": 0,
    "imageready": True,
    "ccdtemperature": -10.0,
    "connecting": False,
}


@pytest.fixture
async def device() -> AsyncIterator[FaultyServer]:
    server = FaultyServer()
    server.replies.update({member: value(v) for member, v in CAMERA_MEMBERS.items()})
    await server.start()
    try:
        yield server
    finally:
        await server.stop()


@pytest.fixture
async def observatory() -> AsyncIterator[Observatory]:
    async with Observatory(clock=RealClock(), site=SIMULATOR_SITE) as obs:
        yield obs


async def start_camera(obs: Observatory, server: FaultyServer, **options: Any) -> AlpacaCamera:
    camera = await obs.start(AlpacaCamera, "camera", server=server.url, **options)
    await camera.set_exposure_time(0.0)
    return camera


async def test_image_bytes_and_the_json_fallback_both_make_the_file(
    device: FaultyServer, observatory: Observatory
) -> None:
    image = np.arange(32, dtype=np.uint16).reshape(4, 8)
    camera = await start_camera(observatory, device)
    device.replies["imagearray"] = image_bytes(imagebytes.encode(image))
    first = await camera.grab_data()
    device.replies["imagearray"] = json_image((image.T + 1).tolist())  # JSON Int32, [x][y]
    second = await camera.grab_data()
    np.testing.assert_array_equal((await observatory.vfs.read_fits(first))[0].data, image)
    np.testing.assert_array_equal((await observatory.vfs.read_fits(second))[0].data, image + 1)


@pytest.mark.parametrize(
    ("reply", "message"),
    [
        (
            "wrong size",
            r"camera 0 at http://127\.0\.0\.1:\d+: GET imagearray: "
            r"got an image of \(3, 8\), expected \(4, 8\)",
        ),
        ("truncated", r"GET imagearray: malformed image: ImageBytes data of 62 bytes do not match a 8x4"),
        ("alpaca error", r"PUT startexposure: InvalidValue \(0x401\): duration too long"),
        ("camera error", r"the camera reports an error \(CameraState 5\)"),
    ],
)
async def test_faults_are_one_error_and_no_file(
    device: FaultyServer, observatory: Observatory, reply: str, message: str
) -> None:
    camera = await start_camera(observatory, device)
    good = imagebytes.encode(np.zeros((4, 8), np.uint16))
    device.replies["imagearray"] = image_bytes(good)
    if reply == "wrong size":
        device.replies["imagearray"] = image_bytes(imagebytes.encode(np.zeros((3, 8), np.uint16)))
    elif reply == "truncated":
        device.replies["imagearray"] = image_bytes(good[:-2])
    elif reply == "alpaca error":
        device.replies["startexposure"] = alpaca_error(0x401, "duration too long")
    else:
        device.replies["camerastate"] = value(5)
    with pytest.raises(GrabImageError, match=message):
        await camera.grab_data()
    assert await observatory.vfs.listdir("/cache") == []
    assert camera.state is ModuleState.READY  # the device answered: it is not gone
    device.replies.update(imagearray=image_bytes(good), startexposure=value(None), camerastate=value(0))
    assert (await camera.grab_data()).endswith(".fits")  # the next call works


async def test_a_hanging_device_is_a_timeout_and_the_module_in_error(
    device: FaultyServer, observatory: Observatory
) -> None:
    camera = await start_camera(observatory, device, readout_timeout=0.3, reconnect_interval=60.0)
    device.replies["imagearray"] = device.hang()
    with pytest.raises(GrabImageError, match=r"GET imagearray: no reply within 0\.3 s"):
        await camera.grab_data()
    assert camera.state is ModuleState.ERROR
    assert "lost camera 0 at" in await camera.get_error_string()
    assert await observatory.vfs.listdir("/cache") == []


@pytest.mark.parametrize(
    ("can_abort", "can_stop", "sent"),
    [(True, True, ["abortexposure"]), (False, True, ["stopexposure"]), (False, False, [])],
)
async def test_an_exposure_left_running_is_aborted_or_stopped_before_the_camera_is_ready(
    device: FaultyServer, observatory: Observatory, can_abort: bool, can_stop: bool, sent: list[str]
) -> None:
    states = iter([2, 0])  # exposing for a camera module that was killed; idle once aborted
    device.replies.update(canabortexposure=value(can_abort), canstopexposure=value(can_stop))

    async def camera_state(request: Any) -> Any:
        return await value(next(states, 0))(request)

    device.replies["camerastate"] = camera_state
    camera = await start_camera(observatory, device)
    assert camera.state is ModuleState.READY
    assert [m for method, m, _ in device.requests if method == "PUT" and m.endswith("exposure")] == sent
