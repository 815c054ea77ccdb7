"""Fixtures of the robotic tests."""

from __future__ import annotations

import shutil
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from nightcrew.night.build import bundled_observatory
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile

from .mastermind_night import Parts


@pytest.fixture
async def parts(tmp_path: Path) -> AsyncIterator[Parts]:
    """A virtual-time observatory and an open SQLite archive on its clock; closed in that order."""
    obs = Observatory()
    archive = SqliteTaskArchive(tmp_path / "tasks.sqlite", clock=obs.clock, poll_interval=0)
    await archive.open()
    try:
        yield obs, archive
    finally:
        await obs.close()
        await archive.close()
        MemoryFile.clear_shared()


@pytest.fixture
def observatory_copy(tmp_path: Path, bundled_xmpp_files: None) -> Path:
    """A copy of the bundled observatory directory (its files only, no data), for ``check``."""
    observatory = tmp_path / "observatory"
    ignore = shutil.ignore_patterns("frames", "xmpp", "logs", "*.sqlite*", "*.jsonl")
    shutil.copytree(bundled_observatory(), observatory, ignore=ignore)
    return observatory
