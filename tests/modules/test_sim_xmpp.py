"""The bundled simulated observatory as six ``nightcrew run`` processes on one Prosody.

Each process runs one of the overlays in ``examples/sim-processes`` (a bundled module file plus an
XmppComm and an accelerated clock); a driver module in this test process opens the roof, points
at M39, sets focus and filter and takes an exposure. The camera process writes the FITS file, with
the headers the *other* processes gave it over XMPP, and real stars in it.
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import sep  # type: ignore[import-not-found]
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.clock import AcceleratedClock
from nightcrew.interfaces import (
    ICamera,
    IExposureTime,
    IFilters,
    IFocuser,
    IImageType,
    ImageType,
    IRoof,
    ITelescope,
)
from nightcrew.modules import Module
from nightcrew.modules.sim.interfaces import ISimFocuserTruth
from nightcrew.testing import modules_ready

# The session's Prosody and a room per test, as tests/comm has them (imported to be found here).
from tests.comm.conftest import Network, prosody_network, prosody_server  # noqa: F401
from tests.modules.sim_processes import CLOCK_SPEED, CLOCK_START, Processes, overlay_environment

pytestmark = pytest.mark.xmpp
MODULES = ["conditions", "roof", "telescope", "focuser", "filters", "camera"]
M39 = (322.95, 48.43)
#: Wall seconds for all processes to come up (the camera loads its star catalog).
START_TIMEOUT = 60.0


@pytest.fixture
def network(request: pytest.FixtureRequest) -> Network:
    prosody: Network = request.getfixturevalue("prosody_network")
    return prosody


@pytest.fixture
def observatory(network: Network, tmp_path: Path) -> Iterator[Processes]:
    """One ``nightcrew run`` process per module in the test's room; images go to tmp_path/images."""
    server = network.server
    assert server is not None and server.ca_file is not None
    env = overlay_environment(server, network.room, tmp_path, MODULES)
    processes = Processes(tmp_path)
    try:
        for name in MODULES:
            processes.start(name, env)
        yield processes
        problems = processes.stop()
    finally:
        processes.kill()  # after a failure: no process outlives the test
    assert not problems, "\n".join(problems)


async def wait_until_ready(driver: Module, processes: Processes) -> None:
    """Until every module is in the room and READY (it joins the room before it is ready)."""
    deadline = time.monotonic() + START_TIMEOUT
    waiting = set(processes.running)
    while waiting:
        processes.check_alive()
        assert time.monotonic() < deadline, f"not ready within {START_TIMEOUT:g} s: {sorted(waiting)}"
        waiting = {name for name in waiting if not await modules_ready(driver, [name])}
        await asyncio.sleep(0.2)


async def observe_m39(driver: Module) -> str:
    """What a script would do: open up, point, focus, choose a filter, expose; the file's VFS path."""
    proxy = driver.comm.proxy
    roof, telescope = await proxy("roof", IRoof), await proxy("telescope", ITelescope)
    await asyncio.gather(roof.open_roof(), telescope.init())
    best_focus = await (await proxy("focuser", ISimFocuserTruth)).get_best_focus()
    await asyncio.gather(
        telescope.move_radec(*M39),
        (await proxy("focuser", IFocuser)).set_focus(round(best_focus, 3)),
        (await proxy("filters", IFilters)).set_filter("R"),
    )
    await (await proxy("camera", IExposureTime)).set_exposure_time(10.0)
    await (await proxy("camera", IImageType)).set_image_type(ImageType.OBJECT)
    filename: str = await (await proxy("camera", ICamera)).grab_data()
    return filename


def count_stars(data: Any) -> int:
    image = np.asarray(data, dtype=np.float64)
    background = sep.Background(image)
    return len(sep.extract(image - background, 5.0, err=background.globalrms, minarea=5))


async def test_six_processes_take_an_exposure_with_headers_from_the_others(
    network: Network, observatory: Processes, tmp_path: Path
) -> None:
    driver = await network.start(Module, "operator", clock=AcceleratedClock(CLOCK_START, speed=CLOCK_SPEED))
    await wait_until_ready(driver, observatory)

    filename = await asyncio.wait_for(observe_m39(driver), 60)

    path = tmp_path / "images" / filename.removeprefix("/images/")
    assert path.is_file(), f"{filename} not in {path.parent}"
    with fits.open(path) as hdus:
        header, data = hdus[0].header, hdus[0].data
        assert header["RA"] == pytest.approx(M39[0], abs=1e-6)  # from the telescope process
        assert header["DEC"] == pytest.approx(M39[1], abs=1e-6)
        assert 1.0 <= header["AIRMASS"] < 2.0
        assert header["FILTER"] == "R"  # from the filter wheel process
        assert 20.0 < header["FOCUS"] < 30.0  # from the focuser process
        assert header["IMAGETYP"] == "object" and header["EXPTIME"] == 10.0
        assert header["DATE-OBS"].startswith("2026-11-10T17:5")  # the shared clock
        assert count_stars(data) > 100
