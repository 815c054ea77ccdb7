"""AutonomousWarning warns, keeps a flag file and runs its command while a module is autonomous."""

from __future__ import annotations

import logging
import sys
from pathlib import Path
from typing import Any

import pytest

from nightcrew.interfaces import IAutonomous
from nightcrew.modules import Module
from nightcrew.modules.utils import AutonomousWarning
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile


class Robot(Module, IAutonomous):
    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.on = False

    async def is_autonomous(self) -> bool:
        return self.on


async def test_warns_while_a_module_is_autonomous(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    # The warning runs a real command: a process outside the event loop, so an accelerated clock
    # (on virtual time the command's timeout would pass before the process could start).
    try:
        async with Observatory(speed=200.0) as obs:
            await _warns_while_autonomous(obs, tmp_path, caplog)
    finally:
        MemoryFile.clear_shared()


async def _warns_while_autonomous(obs: Observatory, tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    robot = await obs.start(Robot, "mastermind")
    beeps = tmp_path / "beeps"
    command = [sys.executable, "-c", f"open({str(beeps)!r}, 'a').write('beep\\n')"]
    warning = await obs.start(
        AutonomousWarning,
        "warning",
        interval=5.0,
        repeat=60.0,
        flag_file="/cache/flag",
        command=command,
    )
    await obs.clock.sleep(10.0)
    assert warning.autonomous == [] and not await obs.vfs.exists("/cache/flag")
    with caplog.at_level(logging.WARNING):
        robot.on = True
        await obs.wait_for(lambda: warning.autonomous == ["mastermind"], 30.0, interval=1.0)
        await obs.wait_for(lambda: beeps.exists(), 4000.0, interval=1.0)  # a Python start takes wall time
    assert "autonomous, may move at any time: mastermind" in caplog.text
    assert await obs.vfs.read_bytes("/cache/flag") == b"mastermind\n"
    robot.on = False
    await obs.wait_for(lambda: warning.autonomous == [], 30.0, interval=1.0)
    await obs.clock.sleep(1.0)
    assert not await obs.vfs.exists("/cache/flag")
    assert beeps.read_text() == "beep\n"
