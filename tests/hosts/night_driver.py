"""The test's side of the multi-host night: an operator module that drives it and checks the copies.

:class:`NightDriver` plays the mastermind's part of a short robotic sequence: before every frame it
makes sure the roof is open, the telescope tracks M 39 and the camera is set up (a restarted module
starts afresh), retrying while modules come and go; then it takes the frame. Every wait is bounded.
"""

from __future__ import annotations

import asyncio
import logging
import time
from pathlib import Path

import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.errors import NightcrewError
from nightcrew.interfaces import ICamera, IExposureTime, IImageType, ImageType, IRoof, ITelescope
from nightcrew.modules import Module
from nightcrew.testing import modules_ready
from tests.hosts.observatory_hosts import Observatory

log = logging.getLogger(__name__)
M39 = (322.95, 48.43)
EXPOSURE = 40.0  # clock seconds: 2 wall seconds at the test's speed, long enough to kill a module in
START_TIMEOUT = 240.0  # wall seconds for every process to come up on a busy machine
COPY_TIMEOUT = 120.0  # wall seconds for a frame's copies to land
PREPARE_TIMEOUT = 180.0  # wall seconds to get roof, telescope and camera ready again


class NightDriver:
    """Drives the sequence from the test process through ``driver`` (an operator module)."""

    def __init__(self, observatory: Observatory, driver: Module) -> None:
        self.observatory = observatory
        self.driver = driver

    async def wait_ready(self, names: list[str], within: float = START_TIMEOUT) -> float:
        """Until every module named is in the room and answers READY; returns the wall seconds taken."""
        started = time.monotonic()
        waiting = set(names)
        while waiting:
            self.observatory.check_alive()
            assert time.monotonic() - started < within, f"not ready in {within:g} s: {sorted(waiting)}"
            for name in sorted(waiting):
                try:
                    if await asyncio.wait_for(modules_ready(self.driver, [name]), 5):
                        waiting.discard(name)
                except TimeoutError:  # a call lost with a connection: ask again
                    continue
            await asyncio.sleep(0.2)
        return time.monotonic() - started

    async def prepare(self, names: list[str]) -> None:
        """Modules ``names`` ready, the roof open, the telescope on M 39, the camera set up."""
        deadline = time.monotonic() + PREPARE_TIMEOUT
        while True:
            try:
                await self.wait_ready(names, within=PREPARE_TIMEOUT)
                proxy = self.driver.comm.proxy
                roof, telescope = await proxy("roof", IRoof), await proxy("telescope", ITelescope)
                if str(await roof.get_motion_status()) != "idle":
                    await asyncio.wait_for(roof.open_roof(), 60)
                status = str(await telescope.get_motion_status())
                if status == "parked":
                    await asyncio.wait_for(telescope.init(), 60)
                if status != "tracking":
                    await asyncio.wait_for(telescope.move_radec(*M39), 60)
                await (await proxy("camera", IExposureTime)).set_exposure_time(EXPOSURE)
                await (await proxy("camera", IImageType)).set_image_type(ImageType.OBJECT)
                return
            except (NightcrewError, TimeoutError) as exc:  # a module restarting, an alarm not yet clear
                assert time.monotonic() < deadline, f"could not prepare within {PREPARE_TIMEOUT:g} s: {exc}"
                log.info("preparing again: %s", exc)
                await asyncio.sleep(0.5)  # a pause between tries, not a synchronisation

    async def camera(self) -> ICamera:
        return await self.driver.comm.proxy("camera", ICamera)

    async def grab(self) -> str:
        return await asyncio.wait_for((await self.camera()).grab_data(), 120)


def copies(directory: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in directory.glob("*.fits")} if directory.is_dir() else {}


def copy_name(frame: str) -> str:
    """The writers' name for the camera's frame ``/images/{DATE-OBS}-{IMAGETYP}-{FILTER}.fits``."""
    return Path(frame).name.split("-object-")[0] + "-object.fits"


def copied(observatory: Observatory, frame: str) -> bool:
    name = copy_name(frame)
    return (observatory.ssh_copies / name).exists() and (observatory.smb_copies / name).exists()


async def wait_copied(observatory: Observatory, frames: list[str], within: float = COPY_TIMEOUT) -> float:
    """Until both servers hold a copy of every frame; returns the wall seconds taken."""
    started = time.monotonic()
    while not all(copied(observatory, frame) for frame in frames):
        observatory.check_alive()
        missing = [frame for frame in frames if not copied(observatory, frame)]
        assert time.monotonic() - started < within, (
            f"no copies of {missing} on both servers within {within:g} s\n"
            + observatory.log("writer-ssh")[-2000:]
            + observatory.log("writer-smb")[-2000:]
        )
        await asyncio.sleep(0.1)
    return time.monotonic() - started


def missing_providers(observatory: Observatory, frame: str) -> set[str]:
    """The header providers that the SSH copy of ``frame`` names in HDRMISS."""
    header = fits.getheader(observatory.ssh_copies / copy_name(frame))
    return set(str(header.get("HDRMISS", "")).split(",")) - {""}


def check_copies(observatory: Observatory, frames: list[str]) -> dict[str, int]:
    """Every frame is on both servers, alike, whole, and has the telescope's and the filter wheel's
    cards or names them in HDRMISS. Returns how many frames name each missing provider."""
    over_ssh, over_smb = copies(observatory.ssh_copies), copies(observatory.smb_copies)
    missing: dict[str, int] = {}
    for frame in frames:
        name = copy_name(frame)
        assert name in over_ssh and name in over_smb, f"{frame} lost"
        assert over_smb[name] == over_ssh[name], f"{name} differs between the SSH and SMB copies"
        with fits.open(observatory.ssh_copies / name) as hdus:
            header = hdus[0].header
            assert hdus[0].data.shape == (header["NAXIS2"], header["NAXIS1"])
            assert header["IMAGETYP"] == "object"
            absent = missing_providers(observatory, frame)
            for provider in absent:
                missing[provider] = missing.get(provider, 0) + 1
            if "telescope" not in absent:
                assert header["RA"] == pytest.approx(M39[0], abs=1e-6), f"{name}: RA {header['RA']}"
            if "filters" not in absent:
                assert header["FILTER"], f"{name}: no FILTER and no HDRMISS naming the filter wheel"
    return missing
