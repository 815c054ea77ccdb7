"""What the scheduler module needs from the outside world, as minimal protocols, and the night.

A block source offers the blocks still to observe (over a task archive: YAML, SQLite, LCO portal
...; see :mod:`nightcrew.robotic.archive_ports`); a schedule writer takes the plan, its
:class:`~nightcrew.robotic.planning.PlannedSlot` values as they are, for the mastermind to read
(from an archive's schedule store). Both are implemented elsewhere; :class:`MemoryScheduleStore` is the
in-process writer for the simulator and the tests.
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import UTC, datetime, timedelta
from typing import Protocol, runtime_checkable

from nightcrew.astro import sun_altitude, sun_crossing
from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.planning import PlannedSlot
from nightcrew.robotic.scheduler.blocks import Night, SchedulableBlock
from nightcrew.site import Site

__all__ = ["BlockSource", "MemoryScheduleStore", "NamedBlockSource", "ScheduleWriter", "night_around"]


@runtime_checkable
class BlockSource(Protocol):
    """Source of the blocks to schedule (those neither done nor expired).

    Not a task archive (:class:`nightcrew.robotic.archives.TaskArchive`): the scheduler only reads
    blocks, and :func:`~nightcrew.robotic.archive_ports.as_block_source` wraps an archive.
    """

    async def get_schedulable_blocks(self) -> list[SchedulableBlock]:
        """The blocks that may still be observed."""
        ...


@runtime_checkable
class NamedBlockSource(BlockSource, Protocol):
    """A block source that also knows the names of its blocks' tasks (for displays of the plan)."""

    async def block_names(self) -> dict[str, str]:
        """Block id → the name of its task, for the blocks that may still be observed."""
        ...


@runtime_checkable
class ScheduleWriter(Protocol):
    """Takes the current schedule.

    Not a schedule store (:class:`nightcrew.robotic.archives.ScheduleStore`): the scheduler only
    writes, and :func:`~nightcrew.robotic.archive_ports.as_schedule_writer` wraps a store.
    """

    async def set_schedule(self, slots: Sequence[PlannedSlot], planned_at: datetime) -> None:
        """Replace the schedule by ``slots`` (ordered by start), planned at ``planned_at``."""
        ...


class MemoryScheduleStore:
    """The schedule in memory, with the time it was planned at (a :class:`ScheduleWriter`)."""

    def __init__(self) -> None:
        self.slots: tuple[PlannedSlot, ...] = ()
        self.planned_at: datetime | None = None

    async def set_schedule(self, slots: Sequence[PlannedSlot], planned_at: datetime) -> None:
        self.slots = tuple(slots)
        self.planned_at = planned_at


def night_around(
    site: Site, now: datetime, *, max_sun_altitude: float = -12.0, step_s: float = 300.0
) -> Night:
    """The night going on at ``now``, or else the next one: while the Sun is below the limit.

    The start is ``now`` when the Sun is already down; edges are found to a second by bisection.
    """

    def next_change(unix_time: float, to_dark: bool) -> float:
        # The Sun crosses any altitude it reaches within a day; two days leave room for the search.
        try:
            return sun_crossing(
                site, unix_time, max_sun_altitude, rising=not to_dark, within=2 * 86400.0, step=step_s
            )
        except ValueError:
            raise InvalidArgumentError(
                f"the Sun does not cross {max_sun_altitude}° near {now} at latitude {site.latitude}"
            ) from None

    now_unix = now.timestamp()
    dark_now = sun_altitude(site.latitude, site.longitude, now_unix) <= max_sun_altitude
    start = now_unix if dark_now else next_change(now_unix, to_dark=True)
    end = next_change(start, to_dark=False)
    epoch = datetime(1970, 1, 1, tzinfo=UTC)
    return Night(epoch + timedelta(seconds=start), epoch + timedelta(seconds=end), site)
