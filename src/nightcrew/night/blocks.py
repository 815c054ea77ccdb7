"""The scheduler's view of the simulated night's archive, calibration tasks included.

The scheduler places blocks by sky position, so :mod:`nightcrew.robotic.tasks.blocks` leaves out
tasks without a target (BIAS, DARK, SKY_FLAT). On the simulated night they must run too, in their
windows: :class:`NightBlockSource` gives each such task a stand-in target near the celestial pole,
which is up all night at the site (the flat-field pointing chooses the real position), so the
scheduler fits them in by window and Sun limit like any other block.

Sky flats wait for the sky to reach the right brightness, so their block is not the sum of their
exposure times but most of the twilight in their window (:data:`TWILIGHT_SHARE`): at dusk they
must then start early, while the sky is still bright enough.
"""

from __future__ import annotations

import functools
import math
from datetime import datetime
from typing import Any

import numpy as np

from nightcrew.astro import sun_altitude
from nightcrew.robotic.archives import SqliteTaskArchive, TaskArchive
from nightcrew.robotic.scheduler import Constraints, SchedulableBlock, Target
from nightcrew.robotic.scheduler.ports import BlockSource
from nightcrew.robotic.tasks import ConfigurationType, Task, estimate_duration
from nightcrew.robotic.tasks.blocks import NOTHING_LEFT_S, block_of
from nightcrew.site import Site

__all__ = [
    "CALIBRATION_WEIGHT",
    "SKY_FLAT_SECONDS",
    "TWILIGHT_SHARE",
    "NightBlockSource",
    "calibration_block",
]

#: Where a task without a target is put for the scheduler: always high up in the north.
_POLE = Target(ra=0.0, dec=89.0)
#: Calibrations are short but the night's data need them: their priority counts this much more.
CALIBRATION_WEIGHT = 10.0
#: Sky flats take this part of the twilight in their window (between their Sun limits).
TWILIGHT_SHARE = 0.75
#: Sky flats take at least this long (also without a site to compute the twilight).
SKY_FLAT_SECONDS = 1800.0


def calibration_block(task: Task, site: Site | None = None) -> SchedulableBlock:
    """A block for a task without a target: its windows, Sun limit and duration, near the pole,
    with its priority weighted by :data:`CALIBRATION_WEIGHT`; sky flats last most of the twilight.
    A retried task's duration is what it has left, as for blocks with a target."""
    estimate = estimate_duration(task.request, progress=task.status.progress)
    configurations = task.request.configurations
    duration = max(sum(estimate.configurations_s), NOTHING_LEFT_S)
    flats = [c for c in configurations if c.type is ConfigurationType.SKY_FLAT]
    if flats:
        duration = max(duration, SKY_FLAT_SECONDS)
        low = flats[0].constraints.min_sun_altitude
        if site is not None and low is not None:
            high = flats[0].constraints.max_sun_altitude
            longest = max(_twilight_seconds(site, w.start, w.end, low, high) for w in task.request.windows)
            duration = max(duration, TWILIGHT_SHARE * longest)
    return SchedulableBlock(
        id=task.id,
        priority=task.effective_priority * CALIBRATION_WEIGHT,
        duration_s=duration,
        target=_POLE,
        constraints=Constraints(
            max_airmass=3.0, max_sun_altitude=min(c.constraints.max_sun_altitude for c in configurations)
        ),
        windows=tuple((window.start, window.end) for window in task.request.windows),
        setup_s=estimate.setup_s,
    )


@functools.lru_cache(maxsize=256)
def _twilight_seconds(site: Site, start: datetime, end: datetime, low: float, high: float) -> float:
    """Seconds (to a minute) between ``start`` and ``end`` with the Sun between ``low`` and ``high``.

    Cached: the scheduler asks for the blocks every poll (a few times a wall second on a fast
    clock); the Sun at every minute of a night window is one array call of about 0.3 ms.
    """
    t0 = start.timestamp()
    minutes = t0 + 60.0 * np.arange(math.ceil((end.timestamp() - t0) / 60.0), dtype=np.float64)
    altitude = sun_altitude(site.latitude, site.longitude, minutes)
    return 60.0 * int(np.count_nonzero((low <= altitude) & (altitude <= high)))


class NightBlockSource(BlockSource):
    """Blocks of every schedulable task of ``archive``, those without a target near the pole.

    Args:
        archive: The task archive (an object, or the path of a SQLite archive).
        site: Where the observatory is, for the twilight of sky flats (None: they take 30 min).
    """

    def __init__(self, *, archive: TaskArchive | str, site: Site | dict[str, Any] | None = None) -> None:
        self.archive = archive if isinstance(archive, TaskArchive) else SqliteTaskArchive(archive)
        self.site = Site(**site) if isinstance(site, dict) else site

    async def get_schedulable_blocks(self) -> list[SchedulableBlock]:
        blocks = []
        for task in await self.archive.get_schedulable_tasks():
            block = block_of(task)
            blocks.append(block if block is not None else calibration_block(task, self.site))
        return blocks

    async def block_names(self) -> dict[str, str]:
        """Block id → task name (a block's id is its task's)."""
        return {task.id: task.name for task in await self.archive.get_schedulable_tasks()}
