"""alpyca, a third-party Alpaca client, drives nightcrew's simulated observatory through AlpacaServer.

Every call goes from alpyca over HTTP to the server, through proxies to the simulated modules, and
back: the management API, the telescope slewing, the camera exposing (the frame alpyca receives
is the FITS file the camera wrote, pixel for pixel), focuser, filter wheel, dome and the weather
verdict as a safety monitor.
"""

from __future__ import annotations

import asyncio
from pathlib import Path

import aiohttp
import numpy as np
import pytest
from alpaca.camera import Camera  # type: ignore[import-untyped]
from alpaca.dome import Dome, ShutterState  # type: ignore[import-untyped]
from alpaca.exceptions import NotImplementedException  # type: ignore[import-untyped]
from alpaca.filterwheel import FilterWheel  # type: ignore[import-untyped]
from alpaca.focuser import Focuser  # type: ignore[import-untyped]
from alpaca.observingconditions import ObservingConditions  # type: ignore[import-untyped]
from alpaca.safetymonitor import SafetyMonitor  # type: ignore[import-untyped]
from alpaca.telescope import Telescope  # type: ignore[import-untyped]
from astropy.io import fits  # type: ignore[import-untyped]

from alpaca import management  # type: ignore[import-untyped]
from nightcrew.config import build_object, load_config, validate_config
from nightcrew.interfaces import MotionStatus
from nightcrew.modules import Module
from nightcrew.modules.alpaca import AlpacaServer
from nightcrew.modules.sim import SimTelescope, SimWeatherStation
from nightcrew.testing import Observatory
from nightcrew.vfs import VirtualFileSystem

from .served import DARK_NIGHT, MILKY_WAY, Served, served_observatory, wait_in_thread


@pytest.fixture
async def served() -> Served:  # type: ignore[misc]
    async with served_observatory() as served:
        yield served


async def test_management_api_lists_every_device_with_a_unique_id(served: Served) -> None:
    versions = await asyncio.to_thread(management.apiversions, served.address)
    description = await asyncio.to_thread(management.description, served.address)
    devices = await asyncio.to_thread(management.configureddevices, served.address)

    assert versions == [1]
    assert description["ServerName"] == "nightcrew"
    assert description["Manufacturer"] == "nightcrew"
    kinds = {(d["DeviceType"], d["DeviceNumber"], d["DeviceName"]) for d in devices}
    assert kinds == {
        ("Telescope", 0, "telescope"),
        ("Camera", 0, "camera"),
        ("Dome", 0, "dome"),
        ("Focuser", 0, "focuser"),
        ("FilterWheel", 0, "filters"),
        ("SafetyMonitor", 0, "weather"),
    }
    ids = [d["UniqueID"] for d in devices]
    assert len(set(ids)) == len(ids) == 6


async def test_unique_ids_stay_the_same_when_the_server_restarts() -> None:
    async with served_observatory() as first:
        before = await asyncio.to_thread(management.configureddevices, first.address)
    async with served_observatory() as second:
        after = await asyncio.to_thread(management.configureddevices, second.address)
    assert [d["UniqueID"] for d in before] == [d["UniqueID"] for d in after]


async def test_alpyca_slews_the_telescope_and_parks_it(served: Served) -> None:
    telescope = Telescope(served.address, 0)
    await asyncio.to_thread(setattr, telescope, "Connected", True)
    assert await asyncio.to_thread(lambda: telescope.AtPark)
    await asyncio.to_thread(telescope.Unpark)
    await wait_in_thread(lambda: not telescope.AtPark and not telescope.Slewing, 10.0, "unparked")

    ra, dec = MILKY_WAY
    await asyncio.to_thread(telescope.SlewToCoordinatesAsync, ra / 15.0, dec)
    # Slewing is true while the nightcrew move runs (see test_abortslew_stops_a_running_slew);
    # afterwards the mount tracks the target it was sent to.
    sim = served.observatory.module("telescope", SimTelescope)
    await wait_in_thread(lambda: not telescope.Slewing, 10.0, "slew finished")
    assert await asyncio.to_thread(lambda: telescope.Tracking)
    got_ra = await asyncio.to_thread(lambda: telescope.RightAscension)
    got_dec = await asyncio.to_thread(lambda: telescope.Declination)
    assert got_ra == pytest.approx(ra / 15.0, abs=1e-6)
    assert got_dec == pytest.approx(dec, abs=1e-6)
    assert await asyncio.to_thread(lambda: telescope.TargetRightAscension) == pytest.approx(ra / 15.0)
    assert await asyncio.to_thread(lambda: telescope.EquatorialSystem) == 2
    lst = await asyncio.to_thread(lambda: telescope.SiderealTime)
    alt, _ = await sim.get_altaz()
    assert await asyncio.to_thread(lambda: telescope.Altitude) == pytest.approx(alt, abs=0.01)
    assert 0.0 <= lst < 24.0

    await asyncio.to_thread(telescope.SlewToAltAzAsync, 200.0, 45.0)
    await wait_in_thread(lambda: not telescope.Slewing, 10.0, "alt/az slew finished")
    assert await asyncio.to_thread(lambda: telescope.Azimuth) == pytest.approx(200.0, abs=1e-6)
    assert not await asyncio.to_thread(lambda: telescope.Tracking)

    await asyncio.to_thread(telescope.Park)
    await wait_in_thread(lambda: telescope.AtPark, 10.0, "parked")
    assert await sim.get_motion_status() is MotionStatus.PARKED


async def test_abortslew_stops_a_running_slew() -> None:
    async with served_observatory(slew_rate=1.0) as served:  # a slew of a minute: one to abort
        await _abort_a_slew(served)


async def _abort_a_slew(served: Served) -> None:
    sim = served.observatory.module("telescope", SimTelescope)
    await sim.init()
    telescope = Telescope(served.address, 0)
    await asyncio.to_thread(setattr, telescope, "Connected", True)
    await asyncio.to_thread(telescope.SlewToAltAzAsync, 180.0, 20.0)
    assert await asyncio.to_thread(lambda: telescope.Slewing)  # a minute-long slew has begun
    assert await sim.get_motion_status() is MotionStatus.SLEWING
    await asyncio.to_thread(telescope.AbortSlew)
    await wait_in_thread(lambda: not telescope.Slewing, 10.0, "slew aborted")
    assert await sim.get_motion_status() is MotionStatus.IDLE


async def test_alpyca_gets_the_frame_the_camera_wrote(served: Served) -> None:
    sim = served.observatory.module("telescope", SimTelescope)
    await sim.init()
    await sim.move_radec(*MILKY_WAY)
    camera = Camera(served.address, 0)
    await asyncio.to_thread(setattr, camera, "Connected", True)
    assert await asyncio.to_thread(lambda: (camera.CameraXSize, camera.CameraYSize)) == (512, 512)
    assert await asyncio.to_thread(lambda: camera.MaxBinX) == 4
    assert await asyncio.to_thread(lambda: (camera.PixelSizeX, camera.PixelSizeY)) == (9.0, 9.0)

    await asyncio.to_thread(camera.StartExposure, 0.5, True)
    await wait_in_thread(lambda: camera.ImageReady, 60.0, "image ready")
    assert await asyncio.to_thread(lambda: camera.CameraState) == 0  # idle again
    assert await asyncio.to_thread(lambda: camera.PercentCompleted) == 100
    assert await asyncio.to_thread(lambda: camera.LastExposureDuration) == 0.5

    raw = await asyncio.to_thread(lambda: camera.ImageArrayRaw)
    info = await asyncio.to_thread(lambda: camera.ImageArrayInfo)
    assert (info.Rank, info.Dimension1, info.Dimension2) == (2, 512, 512)
    received = np.array(raw).reshape(info.Dimension1, info.Dimension2).T  # [x][y] -> [y, x]

    written = await _last_frame(served.observatory.vfs)
    assert written.dtype == np.uint16
    np.testing.assert_array_equal(received, written)
    assert written.std() > 0  # a rendered sky, not a constant


async def test_binned_subframe_as_json_image_array(served: Served) -> None:
    camera = Camera(served.address, 0)
    await asyncio.to_thread(setattr, camera, "Connected", True)
    await asyncio.to_thread(setattr, camera, "BinX", 2)
    assert await asyncio.to_thread(lambda: (camera.BinY, camera.NumX, camera.NumY)) == (2, 256, 256)
    for name, value in (("StartX", 10), ("StartY", 20), ("NumX", 100), ("NumY", 50)):
        await asyncio.to_thread(setattr, camera, name, value)
    await asyncio.to_thread(camera.StartExposure, 0.0, False)  # a bias
    await wait_in_thread(lambda: camera.ImageReady, 60.0, "image ready")

    # Without Accept: application/imagebytes the server answers with the JSON ImageArray.
    async with aiohttp.ClientSession() as session:
        url = f"{served.url}/api/v1/camera/0/imagearray"
        async with session.get(url, params={"ClientTransactionID": "7"}) as response:
            assert response.content_type == "application/json"
            reply = await response.json()
    assert (reply["Type"], reply["Rank"], reply["ErrorNumber"]) == (2, 2, 0)
    assert reply["ClientTransactionID"] == 7
    pixels = np.array(reply["Value"]).T
    assert pixels.shape == (50, 100)

    written = await _last_frame(served.observatory.vfs)
    np.testing.assert_array_equal(pixels, written)
    header = await _last_header(served.observatory.vfs)
    assert (header["IMAGETYP"], header["XBINNING"], header["XORGSUBF"], header["YORGSUBF"]) == (
        "bias",
        2,
        20,
        40,
    )


async def test_abortexposure_leaves_no_image(served: Served) -> None:
    camera = Camera(served.address, 0)
    await asyncio.to_thread(setattr, camera, "Connected", True)
    await asyncio.to_thread(camera.StartExposure, 60.0, True)
    await wait_in_thread(lambda: camera.CameraState == 2, 10.0, "exposing")
    await asyncio.to_thread(camera.AbortExposure)
    assert await asyncio.to_thread(lambda: camera.CameraState) == 0
    assert not await asyncio.to_thread(lambda: camera.ImageReady)
    assert not await served.observatory.vfs.find("/cache/*.fits")


async def test_focuser_filterwheel_dome_and_safety_monitor(served: Served) -> None:
    focuser = Focuser(served.address, 0)
    wheel = FilterWheel(served.address, 0)
    dome = Dome(served.address, 0)
    safety = SafetyMonitor(served.address, 0)
    for device in (focuser, wheel, dome, safety):
        await asyncio.to_thread(setattr, device, "Connected", True)

    assert await asyncio.to_thread(lambda: focuser.Position) == 20000  # 20 mm at 1 µm per step
    await asyncio.to_thread(focuser.Move, 22500)
    await wait_in_thread(lambda: not focuser.IsMoving, 10.0, "focuser arrived")
    assert await asyncio.to_thread(lambda: focuser.Position) == 22500
    assert await asyncio.to_thread(lambda: focuser.StepSize) == pytest.approx(1.0)

    assert await asyncio.to_thread(lambda: wheel.Names) == ["B", "V", "R"]
    await asyncio.to_thread(setattr, wheel, "Position", 2)
    await wait_in_thread(lambda: wheel.Position == 2, 10.0, "filter R in the beam")

    assert await asyncio.to_thread(lambda: dome.ShutterStatus) == ShutterState.shutterClosed
    await asyncio.to_thread(dome.OpenShutter)
    await wait_in_thread(lambda: dome.ShutterStatus == ShutterState.shutterOpen, 10.0, "shutter open")
    await asyncio.to_thread(dome.SlewToAzimuth, 90.0)
    await wait_in_thread(lambda: not dome.Slewing, 10.0, "dome turned")
    assert await asyncio.to_thread(lambda: dome.Azimuth) == pytest.approx(90.0)
    await asyncio.to_thread(dome.CloseShutter)
    await wait_in_thread(lambda: dome.ShutterStatus == ShutterState.shutterClosed, 10.0, "shutter closed")

    # The Sun is 20° down: the weather module's verdict is good, so it is safe.
    await wait_in_thread(lambda: safety.IsSafe, 10.0, "safe")


async def _last_frame(vfs: VirtualFileSystem) -> np.ndarray:
    hdul = await vfs.read_fits(await _last_path(vfs))
    return np.array(hdul[0].data)


async def _last_header(vfs: VirtualFileSystem) -> fits.Header:
    hdul = await vfs.read_fits(await _last_path(vfs))
    return hdul[0].header


async def _last_path(vfs: VirtualFileSystem) -> str:
    paths = sorted(await vfs.find("/cache/*.fits"))
    assert len(paths) == 1, paths
    return paths[0]


def test_the_example_configuration_builds() -> None:
    path = Path(__file__).resolve().parents[2] / "examples" / "alpaca" / "server.yaml"
    config = load_config(path)
    validate_config(config, Module)
    server = build_object({**config, "name": "alpaca"}, Module)
    assert isinstance(server, AlpacaServer)
    assert [d.describe() for d in server.devices] == [
        "telescope 0 (module telescope)",
        "camera 0 (module camera)",
        "dome 0 (module roof)",
        "focuser 0 (module focuser)",
        "filterwheel 0 (module filters)",
        "safetymonitor 0 (module weather)",
        "observingconditions 0 (module conditions)",
    ]


async def test_a_weather_station_as_observing_conditions() -> None:
    scenario = [{"at": 0, "temperature": 8.0, "humidity": 55, "wind_speed": 18.0, "clouds": 0.05}]
    async with Observatory(speed=1.0, epoch=DARK_NIGHT) as obs:
        await obs.start(SimWeatherStation, "station", scenario=scenario)
        server = await obs.start(
            AlpacaServer, "alpaca", devices={"observingconditions": "station"}, port=0, discovery_port=None
        )
        conditions = ObservingConditions(f"127.0.0.1:{server.port}", 0)
        await asyncio.to_thread(setattr, conditions, "Connected", True)
        read = await asyncio.to_thread(
            lambda: (conditions.Temperature, conditions.Humidity, conditions.WindSpeed)
        )
        assert read == pytest.approx((8.0, 55.0, 5.0))  # wind in m/s
        assert "temperature of nightcrew module station" in await asyncio.to_thread(
            conditions.SensorDescription, "Temperature"
        )
        assert await asyncio.to_thread(conditions.TimeSinceLastUpdate, "") >= 0.0
        assert await asyncio.to_thread(lambda: conditions.AveragePeriod) == 0.0
        with pytest.raises(NotImplementedException, match="observingconditions member cloudcover"):
            await asyncio.to_thread(lambda: conditions.CloudCover)
