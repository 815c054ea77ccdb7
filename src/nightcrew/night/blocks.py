"""The scheduler's view of a task archive by name, calibration tasks included (kept for module files).

The calibration blocks live in the robotic layer (:mod:`nightcrew.robotic.tasks.calibration`): a
scheduler configured with a plain archive places them too. :class:`NightBlockSource` is that
archive's block source under the name older module files use
(``archive: {class: nightcrew.night.blocks.NightBlockSource, archive: tasks.sqlite, site: ...}``).
"""

from __future__ import annotations

from typing import Any

from nightcrew.robotic.archive_ports import ArchiveBlockSource
from nightcrew.robotic.archives import SqliteTaskArchive, TaskArchive
from nightcrew.robotic.tasks.calibration import (
    CALIBRATION_WEIGHT,
    SKY_FLAT_SECONDS,
    TWILIGHT_SHARE,
    calibration_block,
)
from nightcrew.site import Site

__all__ = [
    "CALIBRATION_WEIGHT",
    "SKY_FLAT_SECONDS",
    "TWILIGHT_SHARE",
    "NightBlockSource",
    "calibration_block",
]


class NightBlockSource(ArchiveBlockSource):
    """Blocks of every schedulable task of ``archive``, those without a target near the pole.

    Args:
        archive: The task archive (an object, or the path of a SQLite archive).
        site: Where the observatory is, for the twilight of sky flats (None: the scheduler's site).
    """

    def __init__(self, *, archive: TaskArchive | str, site: Site | dict[str, Any] | None = None) -> None:
        super().__init__(
            archive if isinstance(archive, TaskArchive) else SqliteTaskArchive(archive),
            site=Site(**site) if isinstance(site, dict) else site,
        )
