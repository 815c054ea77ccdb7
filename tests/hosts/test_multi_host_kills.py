"""``kill -9`` of every module in turn while the night across three hosts goes on.

For each module: the module is killed (SIGKILL, by the PID its supervisor reports) and a frame is
taken at once, while it is down; its supervisor restarts it, it rejoins, and the sequence goes on (the driver
opens the roof and points the telescope again when a restart left them closed or parked; a frame
the killed camera could not finish is taken again). At the end every frame the sequence got is on
both servers, and every frame has the telescope's and the filter wheel's cards or names them in
HDRMISS.

Two kills look closer. The camera is killed while the filter wheel is stopped: the restarted
camera has heard from no filter wheel yet, and its first frame must still name it in HDRMISS (it
expects it by its ``expect_headers_from``). The file cache is killed while it holds frames that no
writer has copied (the writers are stopped first): it keeps them on disk, so after its restart
the writers, started again, copy every one of them whole.
"""

from __future__ import annotations

import asyncio
import os
import signal
import time

import pytest

from nightcrew.errors import NightcrewError
from tests.hosts.night_driver import NightDriver, check_copies, copied, missing_providers, wait_copied
from tests.hosts.observatory_hosts import HOST_OF, MODULES, Observatory

pytestmark = pytest.mark.xmpp
#: The order of the kills.
KILLS = [
    "filters", "telescope", "roof", "conditions", "watchdog", "mastermind", "writer-ssh", "writer-smb",
    "camera", "cache",
]  # fmt: skip
RESTART_TIMEOUT = 120.0  # wall seconds for a killed module to be back
WRITERS = ["writer-ssh", "writer-smb"]
#: Modules stopped (by request) while a module is killed: whose absence the kill must cope with.
STOPPED_DURING = {"camera": ["filters"], "cache": WRITERS}
HELD_FRAMES = 2  # frames the cache holds, copied by nobody, when it is killed


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


async def frame_with_a_kill(night: NightDriver, name: str, stopped: list[str]) -> tuple[str, float, bool]:
    """Kill ``name`` and take a frame at once, while it is down (and ``stopped`` are stopped); the
    frame (taken again if the camera could not take it), the wall seconds until ``name`` was back,
    and whether the frame had to be taken again."""
    observatory = night.observatory
    running = [module for module in MODULES if module not in stopped]
    await night.prepare(running)
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
        await night.prepare(running)
        frame = await night.grab()
    return frame, back, retried


async def test_every_module_killed_in_turn_loses_no_frame(night: NightDriver) -> None:
    observatory = night.observatory
    await night.wait_ready(MODULES)
    await night.prepare(MODULES)
    frames = [await night.grab()]
    backs: dict[str, float] = {}
    retried: list[str] = []
    held: list[str] = []
    first_of_camera = ""
    for name in KILLS:
        stopped = STOPPED_DURING.get(name, [])
        for module in stopped:
            await observatory.control("stop", module)
        if name == "cache":
            await night.prepare([m for m in MODULES if m not in stopped])
            held = [await night.grab() for _ in range(HELD_FRAMES)]
            assert not any(copied(observatory, frame) for frame in held), "a stopped writer copied"
            frames += held
        frame, backs[name], again = await frame_with_a_kill(night, name, stopped)
        frames.append(frame)
        if name == "camera":
            first_of_camera = frame  # the restarted camera's first frame (its first try failed)
        if again:
            retried.append(name)
        for module in stopped:
            await observatory.control("start", module)
    await night.prepare(MODULES)
    frames.append(await night.grab())
    await wait_copied(observatory, frames)
    missing = check_copies(observatory, frames)
    named = missing_providers(observatory, first_of_camera)
    assert "filters" in named, (
        "the restarted camera's first frame, taken with the filter wheel down, does not name it"
    )
    for host in ("dome", "camera", "office"):
        status = await observatory.status(host)
        assert all(status[name]["restarts"] == 1 for name in status), status
    assert len(set(frames)) == len(frames) == len(KILLS) + 2 + HELD_FRAMES
    print(
        f"\n{len(frames)} frames, all on both servers; back after the kill (s): "
        + ", ".join(f"{name} {seconds:.1f}" for name, seconds in backs.items())
        + f"; frames taken again: {retried or 'none'}; frames naming missing headers: {missing}; "
        f"the restarted camera's first frame has HDRMISS={','.join(sorted(named))}; "
        f"{len(held)} frames held uncopied by the killed cache, all copied after its restart"
    )
