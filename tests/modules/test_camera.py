"""BaseCamera through a real driver: settings, refusals, busy, abort, headers, files and events."""

from __future__ import annotations

import asyncio
import time
from datetime import datetime

import pytest

from nightcrew.config import build_object
from nightcrew.errors import (
    AbortedError,
    ConfigError,
    DeviceBusyError,
    InvalidArgumentError,
    RemoteTimeoutError,
)
from nightcrew.interfaces import (
    Binning,
    ExposureStatus,
    IData,
    IExposureTime,
    ImageType,
    ISpectrograph,
    Window,
)
from nightcrew.interfaces.base import Interface
from nightcrew.modules import Module
from nightcrew.modules.camera import ExposureSettings, Frame
from nightcrew.modules.camera.exposing import ExposingModule
from nightcrew.testing import Observatory

from .devices import GradientCamera, HeaderPeer, ImageListener, LineSpectrograph


async def test_negative_exposure_time_is_refused_and_keeps_the_old_one(observatory: Observatory) -> None:
    camera = await observatory.start(GradientCamera, "camera")
    await camera.set_exposure_time(2.0)
    with pytest.raises(
        InvalidArgumentError, match=r"exposure_time -1\.0 s is out of range for camera: 0\.\.3600 s"
    ):
        await camera.set_exposure_time(-1.0)
    with pytest.raises(InvalidArgumentError, match="exposure_time nan s is out of range"):
        await camera.set_exposure_time(float("nan"))
    assert await camera.get_exposure_time() == 2.0


async def test_unsupported_binning_is_refused_naming_the_supported_ones(observatory: Observatory) -> None:
    camera = await observatory.start(GradientCamera, "camera")
    await camera.set_binning(2, 2)
    with pytest.raises(InvalidArgumentError, match=r"binning 3x3 is not supported; supported: 1x1, 2x2"):
        await camera.set_binning(3, 3)
    assert await camera.get_binning() == Binning(2, 2)
    assert await camera.list_binnings() == [Binning(1, 1), Binning(2, 2)]


@pytest.mark.parametrize(
    "window",
    [(-1, 0, 10, 10), (0, 0, 65, 48), (60, 0, 10, 10), (0, 40, 10, 10), (0, 0, 0, 10), (0, 0, 10, -5)],
)
async def test_window_outside_the_chip_is_refused(observatory: Observatory, window: tuple[int, ...]) -> None:
    camera = await observatory.start(GradientCamera, "camera")
    await camera.set_window(8, 8, 32, 16)
    with pytest.raises(
        InvalidArgumentError, match=r"lies outside the chip \(left=0, top=0, width=64, height=48\)"
    ):
        await camera.set_window(*window)
    assert await camera.get_window() == Window(8, 8, 32, 16)
    assert await camera.get_full_frame() == Window(0, 0, 64, 48)


async def test_cooling_setpoint_out_of_range_is_refused(observatory: Observatory) -> None:
    camera = await observatory.start(GradientCamera, "camera")
    await camera.set_cooling(True, -20.0)
    with pytest.raises(InvalidArgumentError, match=r"setpoint must be within -100..50 °C, got -273"):
        await camera.set_cooling(True, -273.0)
    with pytest.raises(InvalidArgumentError, match=r"reaches -40 °C at best"):
        await camera.set_cooling(True, -60.0)
    status = await camera.get_cooling()
    assert (status.enabled, status.setpoint) == (True, -20.0)


async def test_second_exposure_while_one_runs_is_busy_and_the_first_frame_is_intact(
    observatory: Observatory,
) -> None:
    camera = await observatory.start(GradientCamera, "camera")
    await camera.set_exposure_time(30.0)
    first = asyncio.create_task(camera.grab_data())
    await observatory.clock.sleep(5.0)
    assert await camera.get_exposure_status() is ExposureStatus.EXPOSING
    assert 0 < await camera.get_exposure_progress() < 100
    with pytest.raises(DeviceBusyError, match="already exposing; wait for the frame or abort"):
        await camera.grab_data()
    filename = await first
    hdul = await observatory.vfs.read_fits(filename)
    assert hdul[0].data.shape == (48, 64)
    assert hdul[0].data[47, 63] == 4763
    assert await camera.get_exposure_status() is ExposureStatus.IDLE


async def test_abort_mid_exposure_raises_aborted_and_writes_nothing(observatory: Observatory) -> None:
    camera = await observatory.start(GradientCamera, "camera")
    await camera.set_exposure_time(600.0)
    grab = asyncio.create_task(camera.grab_data())
    await observatory.clock.sleep(5.0)
    await camera.abort()
    with pytest.raises(AbortedError, match="exposure aborted"):
        await grab
    assert await observatory.vfs.find("/cache/*") == []
    assert await camera.get_exposure_status() is ExposureStatus.IDLE
    await camera.set_exposure_time(0.0)
    assert await camera.grab_data()  # usable again


async def test_file_holds_own_and_peer_headers_and_the_event_tells_others(observatory: Observatory) -> None:
    peer = await observatory.start(HeaderPeer, "telescope", cards={"FILTER": "V/2", "OBJECT": "M 42"})
    listener = await observatory.start(ImageListener, "listener")
    camera = await observatory.start(
        GradientCamera, "camera", fits_headers={"INSTRUME": "GradientCam", "OBSERVER": "robot"}
    )
    await camera.set_exposure_time(2.5)
    await camera.set_binning(2, 2)
    await camera.set_window(8, 4, 32, 16)
    filename = await camera.grab_data(image_type=ImageType.DARK)
    assert filename.startswith("/cache/2024-01-15T22-00-")
    assert filename.endswith("-dark-V-2.fits")  # "/" of the filter name sanitised
    header = (await observatory.vfs.read_fits(filename))[0].header
    assert header["EXPTIME"] == 2.5 and header["IMAGETYP"] == "dark"
    assert (header["XBINNING"], header["YBINNING"], header["XORGSUBF"], header["YORGSUBF"]) == (2, 2, 8, 4)
    assert (
        header["CCD-TEMP"] == -10.2 and header["INSTRUME"] == "GradientCam" and header["OBSERVER"] == "robot"
    )
    assert header["FILTER"] == "V/2" and header["OBJECT"] == "M 42" and header["AFTERKEY"] is True
    assert header["SITELAT"] == 51.56 and header["ORIGIN"] == "nightcrew"
    assert header["DATE-OBS"].startswith("2024-01-15T22:00:") and header["MJD-OBS"] > 60324
    start, end = (datetime.fromisoformat(header[key]) for key in ("DATE-OBS", "DATE-END"))
    assert (end - start).total_seconds() == pytest.approx(2.5, abs=0.002)  # start + EXPTIME
    assert (header["NAXIS1"], header["NAXIS2"]) == (16, 8)
    await asyncio.wait_for(listener.arrived.wait(), 5)
    event, sender = listener.images[0]
    assert (event.filename, event.image_type, sender) == (filename, ImageType.DARK, "camera")
    assert peer.calls == 1


async def test_bias_is_zero_seconds_and_no_broadcast_sends_no_event(observatory: Observatory) -> None:
    listener = await observatory.start(ImageListener, "listener")
    camera = await observatory.start(
        GradientCamera, "camera", filename_pattern="/cache/{IMAGETYP}/{EXPTIME}.fits"
    )
    await camera.set_exposure_time(10.0)
    filename = await camera.grab_data(broadcast=False, image_type=ImageType.BIAS)
    assert filename == "/cache/bias/0.0.fits"
    await observatory.clock.sleep(2.0)
    assert listener.images == []


async def test_slow_header_peer_is_left_out_after_its_timeout(observatory: Observatory) -> None:
    await observatory.start(HeaderPeer, "slow", cards={"SLOWKEY": 1}, delay=3600.0)
    await observatory.start(HeaderPeer, "fast", cards={"FASTKEY": 2})
    camera = await observatory.start(GradientCamera, "camera", header_timeout=5.0)
    await camera.set_exposure_time(1.0)
    started = time.monotonic()
    filename = await camera.grab_data()
    took = (time.monotonic() - started) * observatory.clock.speed  # in clock seconds
    assert took < 1.0 + 1.0 + 5.0 + 2.0  # exposure + readout + header timeout + slack
    header = (await observatory.vfs.read_fits(filename))[0].header
    assert header["FASTKEY"] == 2 and "SLOWKEY" not in header


async def test_a_frame_taken_while_a_header_provider_is_down_names_it(observatory: Observatory) -> None:
    peer = await observatory.start(HeaderPeer, "filters", cards={"FILTER": "R"})
    camera = await observatory.start(GradientCamera, "camera")
    await camera.set_exposure_time(1.0)
    first = (await observatory.vfs.read_fits(await camera.grab_data()))[0].header
    assert first["FILTER"] == "R" and "HDRMISS" not in first
    await peer.close()  # killed, restarting, offline: the camera must not pretend nothing is missing
    second = (await observatory.vfs.read_fits(await camera.grab_data()))[0].header
    assert "FILTER" not in second and second["HDRMISS"] == "filters"
    await observatory.start(HeaderPeer, "filters", cards={"FILTER": "R"})  # back
    third = (await observatory.vfs.read_fits(await camera.grab_data()))[0].header
    assert third["FILTER"] == "R" and "HDRMISS" not in third


async def test_a_restarted_camera_names_an_expected_provider_that_is_down(observatory: Observatory) -> None:
    peer = await observatory.start(HeaderPeer, "filters", cards={"FILTER": "R"})
    await peer.close()
    # Fresh cameras (as after a restart) have heard from nobody: only the configured one knows.
    unaware = await observatory.start(GradientCamera, "unaware")
    await unaware.set_exposure_time(1.0)
    assert "HDRMISS" not in (await observatory.vfs.read_fits(await unaware.grab_data()))[0].header
    camera = await observatory.start(GradientCamera, "camera", expect_headers_from=["filters"])
    await camera.set_exposure_time(1.0)
    first = (await observatory.vfs.read_fits(await camera.grab_data()))[0].header
    assert "FILTER" not in first and first["HDRMISS"] == "filters"
    await observatory.start(HeaderPeer, "filters", cards={"FILTER": "R"})
    second = (await observatory.vfs.read_fits(await camera.grab_data()))[0].header
    assert second["FILTER"] == "R" and "HDRMISS" not in second


@pytest.mark.parametrize(
    ("providers", "message"),
    [
        ("filters", r"expected list\[str\] \| None, got str 'filters'"),
        (["filters", ""], "an empty module name"),
        (["filters", "filters"], "names a module twice"),
        (["camera"], "camera cannot provide headers to itself"),
    ],
)
def test_expected_providers_are_checked_when_built(providers: object, message: str) -> None:
    with pytest.raises(ConfigError, match=message) as info:
        build_object(
            {
                "class": "tests.modules.devices.GradientCamera",
                "name": "camera",
                "expect_headers_from": providers,
            }
        )
    assert info.value.key == "expect_headers_from"


class _HungCamera(GradientCamera):
    """A camera whose exposure never ends (a driver stuck in read-out)."""

    async def _hw_expose(self, settings: ExposureSettings) -> Frame:
        await self.clock.sleep(1e9)
        raise AssertionError("never")


class _HungSpectrograph(LineSpectrograph):
    async def _hw_expose_spectrum(self, exposure_time: float) -> Frame:
        await self.clock.sleep(1e9)
        raise AssertionError("never")


@pytest.mark.parametrize(
    ("cls", "interface", "method"),
    [(_HungCamera, IData, "grab_data"), (_HungSpectrograph, ISpectrograph, "grab_spectrum")],
)
async def test_a_hung_exposure_is_noticed_once_overdue_not_after_an_hour(
    observatory: Observatory, cls: type[ExposingModule], interface: type[Interface], method: str
) -> None:
    device = await observatory.start(cls, "device", header_timeout=5.0)
    caller = await observatory.start(Module, "caller")
    await (await caller.comm.proxy("device", IExposureTime)).set_exposure_time(120.0)
    remote = await caller.comm.proxy("device", interface)
    started = observatory.clock.time()
    # exposure 120 s + read-out 60 s (the default) + header round 5 s + margin 60 s
    # + 10 wall seconds (clock speed 1): 255 s, not the interface's 3600.
    with pytest.raises(RemoteTimeoutError, match=rf"{method}\(\) did not finish within 255 s"):
        await getattr(remote, method)()
    assert 255 <= observatory.clock.time() - started < 270
    if isinstance(device, _HungCamera):  # a bias exposes for no time
        assert device.grab_timeout(ImageType.BIAS) == 135.0
