"""``kill -9`` of every module in turn while the night across three hosts goes on.

For each module: the module is killed (SIGKILL, by the PID its supervisor reports) and a frame is
taken at once, while it is down; its supervisor restarts it, it rejoins, and the sequence goes on (the driver
opens the roof and points the telescope again when a restart left them closed or parked; a frame
the killed camera could not finish is taken again). At the end every frame the sequence got is on
both servers, and every frame has the telescope's and the filter wheel's cards or names them in
HDRMISS. The file cache keeps frames in memory only: it is killed once its frames are copied.
"""

from __future__ import annotations

import asyncio
import os
import signal
import time

import pytest

from nightcrew.errors import NightcrewError
from tests.hosts.night_driver import NightDriver, check_copies, wait_copied
from tests.hosts.observatory_hosts import HOST_OF, MODULES, Observatory

pytestmark = pytest.mark.xmpp
#: The order of the kills; the cache last (its frames are in memory: they must be copied first).
KILLS = [
    "filters", "telescope", "roof", "weather", "watchdog", "mastermind", "writer-ssh", "writer-smb",
    "camera", "cache",
]  # fmt: skip
RESTART_TIMEOUT = 120.0  # wall seconds for a killed module to be back


async def restarted(observatory: Observatory, name: str, old_pid: int) -> None:
    """Until the supervisor runs ``name`` again under a new PID, having counted the restart."""
    deadline = time.monotonic() + RESTART_TIMEOUT
    while True:
        observatory.check_alive()
        module = (await observatory.status(HOST_OF[name]))[name]
        if module["state"] == "running" and module["pid"] != old_pid and module["restarts"] >= 1:
            return
        assert time.monotonic() < deadline, f"{name} not restarted within {RESTART_TIMEOUT:g} s: {module}"
        await asyncio.sleep(0.1)


async def frame_with_a_kill(night: NightDriver, name: str) -> tuple[str, float, bool]:
    """Kill ``name`` and take a frame at once, while it is down; the frame (taken again if the
    camera could not take it), the wall seconds until ``name`` was back, and whether the frame had
    to be taken again."""
    observatory = night.observatory
    await night.prepare(MODULES)
    pid = (await observatory.status(HOST_OF[name]))[name]["pid"]
    os.kill(pid, signal.SIGKILL)
    killed = time.monotonic()
    try:
        frame: str | None = await night.grab()
    except (NightcrewError, TimeoutError):
        frame = None  # the camera (or its cache) is down: the task is tried again
    await restarted(observatory, name, pid)
    await night.wait_ready([name], within=RESTART_TIMEOUT)
    back = time.monotonic() - killed
    retried = frame is None
    if frame is None:
        await night.prepare(MODULES)
        frame = await night.grab()
    return frame, back, retried


async def test_every_module_killed_in_turn_loses_no_frame(night: NightDriver) -> None:
    observatory = night.observatory
    await night.wait_ready(MODULES)
    await night.prepare(MODULES)
    frames = [await night.grab()]
    backs: dict[str, float] = {}
    retried = []
    for name in KILLS:
        if name == "cache":
            await wait_copied(observatory, frames)
        frame, backs[name], again = await frame_with_a_kill(night, name)
        frames.append(frame)
        if again:
            retried.append(name)
    await night.prepare(MODULES)
    frames.append(await night.grab())
    await wait_copied(observatory, frames)
    missing = check_copies(observatory, frames)
    for host in ("dome", "camera", "office"):
        status = await observatory.status(host)
        assert all(status[name]["restarts"] == 1 for name in status), status
    assert len(set(frames)) == len(frames) == len(KILLS) + 2
    print(
        f"\n{len(frames)} frames, all on both servers; back after the kill (s): "
        + ", ".join(f"{name} {seconds:.1f}" for name, seconds in backs.items())
        + f"; frames taken again: {retried or 'none'}; frames naming missing headers: {missing}"
    )
