"""The scheduler's ports on top of the task archives of :mod:`nightcrew.robotic.archives`.

The scheduler module speaks two small protocols (:mod:`.ports`); the archives have richer
interfaces. These adapters join them, so a module file can name an archive directly.
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import datetime

from nightcrew.robotic import archives
from nightcrew.robotic.scheduler.blocks import ScheduledSlot
from nightcrew.robotic.scheduler.ports import BlockSource, ScheduleWriter
from nightcrew.robotic.scheduler.sky import GridFit
from nightcrew.robotic.tasks.blocks import ArchiveBlockSource
from nightcrew.site import Site

__all__ = ["ArchiveScheduleWriter", "as_block_source", "as_schedule_writer"]


class ArchiveScheduleWriter:
    """Writes schedules into an archive's schedule store, from the planning time on."""

    def __init__(self, store: archives.ScheduleStore) -> None:
        self.store = store

    async def set_schedule(self, slots: Sequence[ScheduledSlot], planned_at: datetime) -> None:
        # The slot running now started before planned_at: the archive keeps its own entry for it.
        entries = [archives.ScheduleEntry(s.block_id, s.start, s.end) for s in slots if s.start >= planned_at]
        await self.store.write_schedule(entries, replace_from=planned_at)


def as_block_source(value: object, *, site: Site | None = None, fit: GridFit | None = None) -> BlockSource:
    """``value`` as a block source: an archive of tasks is wrapped, a block source kept.

    ``site`` and ``fit`` (the scheduler's own) place the calibration tasks: sky flats in the
    twilight at the site, as long as fits the scheduler's grid. An :class:`ArchiveBlockSource`
    given without a site takes ``site``.
    """
    if isinstance(value, archives.TaskArchive):
        return ArchiveBlockSource(value, site=site, fit=fit)
    if isinstance(value, ArchiveBlockSource):
        value.site = value.site or site
        value.fit = fit or value.fit
        return value
    if isinstance(value, BlockSource):
        return value
    raise TypeError(f"expected a task archive or a block source, got {type(value).__name__}")


def as_schedule_writer(value: object) -> ScheduleWriter:
    """``value`` as a schedule writer: an archive's schedule store is wrapped, a writer kept."""
    if isinstance(value, archives.ScheduleStore):
        return ArchiveScheduleWriter(value)
    if isinstance(value, ScheduleWriter):
        return value
    raise TypeError(f"expected a schedule store or a schedule writer, got {type(value).__name__}")
