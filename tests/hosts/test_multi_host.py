"""A short night across three simulated hosts; then the office-dome link is cut and restored.

See observatory_hosts.py for who runs where. Frames go camera → its file cache → (office) image
writers → the dome's OpenSSH and Samba. The test checks every copy arrives whole on both servers,
that a cut link really cuts (no copy arrives while it is down), and that once it is mended every
module answers again and new frames are copied again.
"""

from __future__ import annotations

import asyncio
import os
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.clock import AcceleratedClock
from nightcrew.comm.xmpp import XmppComm
from nightcrew.interfaces import ICamera, IExposureTime, IImageType, ImageType, IModule, IRoof, ITelescope
from nightcrew.modules import Module
from nightcrew.testing.hosts import hosts_missing
from nightcrew.testing.samba import samba_missing
from nightcrew.testing.sshd import sshd_missing
from tests.hosts.observatory_hosts import (
    CLOCK_SPEED,
    CLOCK_START,
    DOMAIN,
    MODULES,
    PASSWORD,
    ROOM,
    Observatory,
    start,
    stop,
)
from tests.vfs.remote_servers import require

pytestmark = pytest.mark.xmpp
M39 = (322.95, 48.43)
START_TIMEOUT = 120.0  # wall seconds for every process to come up on a busy machine
COPY_TIMEOUT = 60.0  # wall seconds for a frame's copies to land
#: How long the office-dome link stays cut: longer than the SSH root's keepalive limit (3 x 2 s).
#: NIGHTCREW_CUT_SECONDS=120 gives the issue's two minutes (the suite keeps it short).
CUT_SECONDS = float(os.environ.get("NIGHTCREW_CUT_SECONDS", "15"))


@pytest.fixture
def observatory(tmp_path: Path) -> Iterator[Observatory]:
    require(hosts_missing() + sshd_missing() + samba_missing() + _prosody_missing())
    built = start(tmp_path)
    try:
        yield built
    finally:
        problems = stop(built)
    assert not problems, "\n".join(problems)


def _prosody_missing() -> list[str]:
    import shutil

    return [] if shutil.which("prosody") else ["prosody (apt-get install prosody)"]


async def wait_ready(driver: Module, observatory: Observatory, names: list[str]) -> float:
    """Until every module named is in the room and answers READY; returns the wall seconds taken."""
    started = time.monotonic()
    waiting = set(names)
    while waiting:
        observatory.check_alive()
        assert time.monotonic() - started < START_TIMEOUT, (
            f"not ready in {START_TIMEOUT:g} s: {sorted(waiting)}"
        )
        for name in sorted(waiting & set(driver.comm.clients)):
            try:
                module = await driver.comm.proxy(name, IModule)
                if str(await asyncio.wait_for(module.get_state(), 5)) == "ready":
                    waiting.discard(name)
            except Exception:  # gone again, or a call lost with a connection: ask again
                continue
        await asyncio.sleep(0.2)
    return time.monotonic() - started


def copies(directory: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in directory.glob("*.fits")} if directory.is_dir() else {}


def copy_name(frame: str) -> str:
    """The writers' name for the camera's frame ``/images/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits``."""
    return Path(frame).name.split("-object-")[0] + "-object.fits"


async def wait_copied(observatory: Observatory, frame: str) -> float:
    """Until both servers hold a copy of ``frame``; returns the wall seconds taken."""
    started, name = time.monotonic(), copy_name(frame)
    while not ((observatory.ssh_copies / name).exists() and (observatory.smb_copies / name).exists()):
        observatory.check_alive()
        assert time.monotonic() - started < COPY_TIMEOUT, (
            f"no copy of {frame} on both servers within {COPY_TIMEOUT:g} s\n"
            + observatory.log("writer-ssh")[-2000:]
            + observatory.log("writer-smb")[-2000:]
        )
        await asyncio.sleep(0.1)
    return time.monotonic() - started


def check_copies(observatory: Observatory, at_least: int) -> None:
    """Both servers hold at least ``at_least`` whole frames with the telescope's headers, the same
    frame alike on both."""
    over_ssh, over_smb = copies(observatory.ssh_copies), copies(observatory.smb_copies)
    assert len(over_ssh) >= at_least and len(over_smb) >= at_least, (sorted(over_ssh), sorted(over_smb))
    for name in over_ssh.keys() & over_smb.keys():
        assert over_smb[name] == over_ssh[name], f"{name} differs between the SSH and SMB copies"
    for path in [*observatory.ssh_copies.glob("*.fits"), *observatory.smb_copies.glob("*.fits")]:
        with fits.open(path) as hdus:
            header = hdus[0].header
            assert header["IMAGETYP"] == "object"
            assert header["RA"] == pytest.approx(M39[0], abs=1e-6)
            assert hdus[0].data.shape == (header["NAXIS2"], header["NAXIS1"])


async def test_a_night_across_three_hosts_survives_a_cut_link(observatory: Observatory) -> None:
    comm = XmppComm(
        f"operator@{DOMAIN}", PASSWORD, server=observatory.xmpp_server, room=ROOM, ca_file=observatory.ca_file
    )
    driver = Module(comm=comm, clock=AcceleratedClock(CLOCK_START, speed=CLOCK_SPEED))
    await driver.open()
    try:
        startup = await wait_ready(driver, observatory, MODULES)
        proxy = driver.comm.proxy
        roof, telescope = await proxy("roof", IRoof), await proxy("telescope", ITelescope)
        camera = await proxy("camera", ICamera)
        await asyncio.wait_for(asyncio.gather(roof.open_roof(), telescope.init()), 60)
        await asyncio.wait_for(telescope.move_radec(*M39), 60)
        await (await proxy("camera", IExposureTime)).set_exposure_time(5.0)
        await (await proxy("camera", IImageType)).set_image_type(ImageType.OBJECT)

        first = []
        for _ in range(2):
            frame = await asyncio.wait_for(camera.grab_data(), 60)
            first.append(await wait_copied(observatory, frame))
        check_copies(observatory, 2)

        observatory.hosts.cut("office", "dome")
        cut_at = time.monotonic()
        during = await asyncio.wait_for(camera.grab_data(), 60)  # camera and dome still talk
        await asyncio.sleep(max(0.0, CUT_SECONDS - (time.monotonic() - cut_at)))  # the fault's length
        assert len(copies(observatory.ssh_copies)) == 2, "a copy crossed a cut link"
        assert len(copies(observatory.smb_copies)) == 2, "a copy crossed a cut link"
        observatory.hosts.restore("office", "dome")

        back = await wait_ready(driver, observatory, ["writer-ssh", "writer-smb"])
        frame = await asyncio.wait_for(camera.grab_data(), 60)
        after = await wait_copied(observatory, frame)
        late = [(d / copy_name(during)).exists() for d in (observatory.ssh_copies, observatory.smb_copies)]
        check_copies(observatory, 3)
        print(
            f"\nstart-up {startup:.1f} s; the first two frames copied after {first[0]:.1f} s and "
            f"{first[1]:.1f} s; link cut {CUT_SECONDS:g} s; the office answered {back:.1f} s after "
            f"the restore; a new frame copied after {after:.1f} s; the frame taken during the cut "
            f"copied late over SSH: {late[0]}, over SMB: {late[1]}"
        )
    finally:
        await driver.close()
