"""The scheduler's view of the simulated night's archive, calibration tasks included.

The scheduler places blocks by sky position, so :mod:`nightcrew.robotic.tasks.blocks` leaves out
tasks without a target (BIAS, DARK, SKY_FLAT). On the simulated night they must run too, in their
windows: :class:`NightBlockSource` gives each such task a stand-in target near the celestial pole,
which is up all night at the site (the flat-field pointing chooses the real position), so the
scheduler fits them in by window and Sun limit like any other block.
"""

from __future__ import annotations

from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.archives import TaskArchive as TaskStore
from nightcrew.robotic.scheduler import Constraints, SchedulableBlock, Target
from nightcrew.robotic.scheduler.ports import TaskArchive
from nightcrew.robotic.tasks import ConfigurationType, Task, estimate_duration
from nightcrew.robotic.tasks.blocks import block_of

__all__ = ["CALIBRATION_WEIGHT", "SKY_FLAT_SECONDS", "NightBlockSource", "calibration_block"]

#: Where a task without a target is put for the scheduler: always high up in the north.
_POLE = Target(ra=0.0, dec=89.0)
#: Calibrations are short but the night's data need them: their priority counts this much more.
CALIBRATION_WEIGHT = 10.0
#: Sky flats wait for the sky to reach the right brightness: they take this long of twilight, not
#: the sum of their exposure times (a slot that short would end while the roof is still opening).
SKY_FLAT_SECONDS = 1800.0


def calibration_block(task: Task) -> SchedulableBlock:
    """A block for a task without a target: its windows, Sun limit and duration, near the pole,
    with its priority weighted by :data:`CALIBRATION_WEIGHT`."""
    estimate = estimate_duration(task.request)
    configurations = task.request.configurations
    duration = sum(estimate.configurations_s)
    if any(c.type is ConfigurationType.SKY_FLAT for c in configurations):
        duration = max(duration, SKY_FLAT_SECONDS)
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


class NightBlockSource(TaskArchive):
    """Blocks of every schedulable task of ``archive``, those without a target near the pole.

    Args:
        archive: The task archive (an object, or the path of a SQLite archive).
    """

    def __init__(self, *, archive: TaskStore | str) -> None:
        self.archive = archive if isinstance(archive, TaskStore) else SqliteTaskArchive(archive)

    async def get_schedulable_blocks(self) -> list[SchedulableBlock]:
        blocks = []
        for task in await self.archive.get_schedulable_tasks():
            block = block_of(task)
            blocks.append(block if block is not None else calibration_block(task))
        return blocks
