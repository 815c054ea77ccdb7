"""The progress of a night's cadence requests, read from its task archive for the night report."""

from __future__ import annotations

import asyncio
from pathlib import Path

from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.tasks import cadence_summaries

__all__ = ["stored_cadences"]


def stored_cadences(database: Path) -> list[tuple[str, str]]:
    """``(name, progress)`` of each cadence in the task archive ``database`` (none if it is missing).

    Blocking (it runs its own event loop): call it where no loop runs, as the report commands do.
    """
    if not database.is_file():
        return []

    async def read() -> list[tuple[str, str]]:
        async with SqliteTaskArchive(database, poll_interval=0) as archive:
            return cadence_summaries(await archive.list_tasks())

    return asyncio.run(read())
