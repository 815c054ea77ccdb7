"""The scheduler's ports on top of the task archives of :mod:`nightcrew.robotic.archives`.

The scheduler module speaks two small protocols (:mod:`nightcrew.robotic.scheduler.ports`); the
archives have richer interfaces. These adapters join them, so a module file can name an archive
directly. They sit above scheduler, tasks and archives, so that the first two stay pure (no
archive, hence no clock or file: the import-linter contract in pyproject.toml).
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import datetime

from nightcrew.robotic import archives
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.scheduler.blocks import SchedulableBlock
from nightcrew.robotic.scheduler.ports import BlockSource, ScheduleWriter
from nightcrew.robotic.scheduler.sky import GridFit
from nightcrew.robotic.tasks import DEFAULT_OVERHEADS, OverheadModel
from nightcrew.robotic.tasks.blocks import every_block
from nightcrew.site import Site

__all__ = ["ArchiveBlockSource", "ArchiveScheduleWriter", "as_block_source", "as_schedule_writer"]


class ArchiveBlockSource:
    """The scheduler's view of a task archive: ``await source.get_schedulable_blocks()``.

    Every schedulable task gets a block: those with a target by
    :func:`~nightcrew.robotic.tasks.blocks.block_of`, the others
    (calibrations) by :func:`~nightcrew.robotic.tasks.calibration.calibration_block`.

    Args:
        archive: Where the tasks come from.
        overheads: For the durations.
        site: Where the observatory is, for the twilight of sky flats (None: they take 30 min).
        fit: The scheduler's grid, so that sky flats fit their twilight.
    """

    def __init__(
        self,
        archive: archives.TaskArchive,
        overheads: OverheadModel = DEFAULT_OVERHEADS,
        *,
        site: Site | None = None,
        fit: GridFit | None = None,
    ) -> None:
        self.archive = archive
        self.overheads = overheads
        self.site = site
        self.fit = fit or GridFit()

    async def get_schedulable_blocks(self) -> list[SchedulableBlock]:
        """Blocks of the archive's schedulable tasks, calibrations included."""
        tasks = await self.archive.get_schedulable_tasks()
        return every_block(tasks, self.site, fit=self.fit, overheads=self.overheads)

    async def block_names(self) -> dict[str, str]:
        """Block id → task name (a block's id is its task's)."""
        return {task.id: task.name for task in await self.archive.get_schedulable_tasks()}


class ArchiveScheduleWriter:
    """Writes schedules into an archive's schedule store, from the planning time on."""

    def __init__(self, store: archives.ScheduleStore) -> None:
        self.store = store

    async def set_schedule(self, slots: Sequence[PlannedSlot], planned_at: datetime) -> None:
        # The slot running now started before planned_at: the archive keeps its own copy of it.
        await self.store.write_schedule([s for s in slots if s.start >= planned_at], replace_from=planned_at)


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
