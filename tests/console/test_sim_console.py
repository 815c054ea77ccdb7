"""``nightcrew sim --console``: the simulated night watched live - the mastermind, the plan, the frames."""

from __future__ import annotations

import asyncio
import os
import re
import signal
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import aiohttp

from .conftest import ApiClient, Socket

REPOSITORY = Path(__file__).resolve().parents[2]
#: Wall seconds for the whole run: four clock hours at 320x are ~45 s, plus start-up, on a busy machine.
#: The test stops the night (Ctrl-C) as soon as it has seen what it wants; the hours are a margin.
NIGHT_PATIENCE = 240.0


async def test_the_simulated_night_is_watched_live(
    tmp_path: Path, clients: Callable[[str], ApiClient]
) -> None:
    process = await asyncio.create_subprocess_exec(
        sys.executable,
        "-m",
        "nightcrew",
        "sim",
        "--console",
        "0",
        "--start",
        "19:00",
        "--hours",
        "4",
        "--weather",
        "clear",
        "--out",
        str(tmp_path / "night"),
        cwd=REPOSITORY,
        env={**os.environ, "NIGHTCREW_CONSOLE_PASSWORD": "watch-the-night"},
        stdin=asyncio.subprocess.DEVNULL,
        stdout=asyncio.subprocess.DEVNULL,
        stderr=asyncio.subprocess.PIPE,
    )
    drain: asyncio.Task[bytes] | None = None
    try:
        async with asyncio.timeout(NIGHT_PATIENCE):
            url = await _welcome(process)
            assert process.stderr is not None
            drain = asyncio.create_task(process.stderr.read())  # a full pipe would stall the night
            client = clients(url)
            assert (await client.login("operator", "watch-the-night"))[0] == 200
            socket = Socket(await client.http.ws_connect(client.base + "/api/ws"))
            seen = await _watch(socket)
            image = seen["image"]
            status, png, headers = await client.get_bytes(f"/api/images/{image['module']}/latest.png")
            assert status == 200 and png.startswith(b"\x89PNG") and int(headers["X-Image-Width"]) > 0
            process.send_signal(signal.SIGINT)  # seen enough: stop the night as Ctrl-C does
            await process.wait()
    finally:
        if process.returncode is None:
            process.kill()
            await process.wait()
        if drain is not None:
            await drain
    # 130: "night stopped early" (after parking and closing); 0 if the night ended by itself first.
    assert process.returncode in (0, 130)
    robotic = seen["robotic"]
    assert robotic["mastermind"]["status"]["running"] is True
    assert robotic["mastermind"]["status"]["action"] in (
        "run_task",
        "open_up",
        "focus",
        "wait",
        "close_and_park",
    )
    assert robotic["scheduler"]["plan"]["slots"], "the plan has tasks"
    assert robotic["sun"] and all(point["altitude"] < 0 for point in robotic["sun"][:3])


async def _welcome(process: asyncio.subprocess.Process) -> str:
    assert process.stderr is not None
    while True:
        line = (await process.stderr.readline()).decode()
        assert line, "the night ended before the console was served"
        found = re.search(r"nightcrew console at (http://127\.0\.0\.1:\d+/)", line)
        if found:
            return found.group(1)


async def _watch(socket: Socket) -> dict[str, Any]:
    """The first robotic message with a running task and a plan, and the first new frame."""
    seen: dict[str, Any] = {}

    def wanted(message: dict[str, Any]) -> bool:
        if message["type"] == "image":
            seen.setdefault("image", message)
        elif message["type"] == "robotic":
            master, planner = message["mastermind"], message["scheduler"]
            if master and master["status"] and planner and planner["plan"]:
                seen.setdefault("robotic", message)
        return "image" in seen and "robotic" in seen

    while not wanted(await _next(socket)):
        pass
    return seen


async def _next(socket: Socket) -> dict[str, Any]:
    received = await socket.socket.receive()
    assert received.type is aiohttp.WSMsgType.TEXT, f"the console went away ({received.type})"
    message: dict[str, Any] = received.json()
    return message
