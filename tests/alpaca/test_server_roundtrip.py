"""nightcrew on both ends of Alpaca: nightcrew's Alpaca client modules drive nightcrew's simulated
devices through AlpacaServer, as they would drive any Alpaca server.

A second observatory (its own network and VFS, the same clock) runs AlpacaTelescope, AlpacaCamera,
AlpacaFocuser and AlpacaFilterWheel pointed at the server; what they do must arrive at the
simulated devices, and the frame the Alpaca camera writes must hold the simulated camera's pixels.
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from dataclasses import dataclass

import numpy as np
import pytest

from nightcrew.interfaces import ExposureStatus, ImageType
from nightcrew.modules.alpaca.camera import AlpacaCamera
from nightcrew.modules.alpaca.filterwheel import AlpacaFilterWheel
from nightcrew.modules.alpaca.focuser import AlpacaFocuser
from nightcrew.modules.alpaca.telescope import AlpacaTelescope
from nightcrew.modules.sim import SimCamera, SimFilterWheel, SimFocuser, SimTelescope
from nightcrew.testing import SITE, Observatory, wait_for

from .served import MILKY_WAY, Served, served_observatory


@dataclass
class Both:
    served: Served
    client: Observatory


@pytest.fixture
async def both() -> AsyncIterator[Both]:
    # One clock (real-time rate, a dark night) on both sides, so they agree on the sky.
    async with (
        served_observatory() as served,
        Observatory(clock=served.observatory.clock, site=SITE) as client,
    ):
        yield Both(served, client)


async def test_alpaca_modules_drive_the_served_simulator(both: Both) -> None:
    url = both.served.url
    telescope = await both.client.start(AlpacaTelescope, "telescope", server=url)
    focuser = await both.client.start(AlpacaFocuser, "focuser", server=url)
    wheel = await both.client.start(AlpacaFilterWheel, "filters", server=url)
    sim = both.served.observatory

    await telescope.init()
    await telescope.move_radec(*MILKY_WAY)
    ra, dec = await sim.module("telescope", SimTelescope).get_radec()
    assert (ra, dec) == pytest.approx(MILKY_WAY, abs=1e-6)
    assert await telescope.get_radec() == pytest.approx(MILKY_WAY, abs=1e-6)

    await focuser.set_focus(21.5)
    assert await sim.module("focuser", SimFocuser).get_focus() == pytest.approx(21.5)
    assert await wheel.list_filters() == ["B", "V", "R"]
    await wheel.set_filter("V")
    assert await sim.module("filters", SimFilterWheel).get_filter() == "V"

    await telescope.park()
    assert await sim.module("telescope", SimTelescope).get_motion_status() == "parked"


async def test_the_alpaca_camera_writes_the_simulated_frame(both: Both) -> None:
    camera = await both.client.start(AlpacaCamera, "camera", server=both.served.url)
    await camera.set_binning(2, 2)
    await camera.set_exposure_time(0.2)
    path = await camera.grab_data(image_type=ImageType.DARK)

    client_file = await both.client.vfs.read_fits(path)
    (served_path,) = await both.served.observatory.vfs.find("/cache/*.fits")
    served_file = await both.served.observatory.vfs.read_fits(served_path)
    assert client_file[0].data.shape == (256, 256)
    np.testing.assert_array_equal(client_file[0].data, served_file[0].data)
    assert served_file[0].header["IMAGETYP"] == "dark"
    assert (client_file[0].header["EXPTIME"], served_file[0].header["EXPTIME"]) == (0.2, 0.2)


async def test_stop_exposure_through_alpaca_keeps_the_frame_cut_short(both: Both) -> None:
    camera = await both.client.start(AlpacaCamera, "camera", server=both.served.url)
    await camera.set_binning(4, 4)
    await camera.set_exposure_time(30.0)
    grab = asyncio.ensure_future(camera.grab_data(image_type=ImageType.OBJECT))
    sim_camera = both.served.observatory.module("camera", SimCamera)
    clock = both.served.observatory.clock

    async def exposing() -> bool:
        return await sim_camera.get_exposure_status() is ExposureStatus.EXPOSING

    await wait_for(exposing, 10.0, clock=clock, message="the served camera exposes")
    assert await camera.device.get("canstopexposure") is True
    await camera.stop_exposure()
    async with clock.timeout(20.0):
        client_file = await grab

    client = (await both.client.vfs.read_fits(client_file))[0].header
    (served_path,) = await both.served.observatory.vfs.find("/cache/*.fits")
    served = (await both.served.observatory.vfs.read_fits(served_path))[0].header
    assert client["CUTSHORT"] is served["CUTSHORT"] is True
    assert client["EXPREQ"] == served["EXPREQ"] == 30.0
    assert served["EXPTIME"] < 20.0 and client["EXPTIME"] < 20.0
    assert await camera.device.get("lastexposureduration") == served["EXPTIME"]
