"""From tasks to the scheduler's :class:`~nightcrew.robotic.scheduler.SchedulableBlock` values.

The scheduler knows nothing of the task model; this adapter gives it what it needs of each task:

- ``id``: the task id; ``priority``: priority x IPP; ``windows``: the request's windows;
- ``duration_s``: the configurations' estimated time, ``setup_s``: the request's own set-up
  (both from an :class:`OverheadModel`; the scheduler adds its slew overhead on top). A task
  retried after an interruption is planned for what it has left (its recorded progress), so it
  reserves no night time for exposures it has, and is weighted by the time it still observes;
- ``target``: the first configuration's target (proper motion and epoch kept);
- ``constraints``: the strictest limits over all configurations;
- ``early_start_weight``: by the observation type (:data:`EARLY_START_WEIGHTS`): a time-critical
  or rapid-response request starts as early as its window and the telescope allow.

A task without any target (only BIAS, DARK, SKY_FLAT or SCRIPT configurations) has no block of
its own: :func:`blocks_of` lists it in :attr:`BlockConversion.left_out`, and
:func:`every_block` (what the scheduler reads, through
:class:`~nightcrew.robotic.archive_ports.ArchiveBlockSource`) gives it a calibration block
(:mod:`.calibration`: near the pole, by window and Sun; sky flats in the site's twilight).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from nightcrew.robotic.scheduler import Constraints, SchedulableBlock, Target
from nightcrew.robotic.scheduler.moving import EphemerisTarget
from nightcrew.robotic.scheduler.sky import GridFit
from nightcrew.robotic.tasks._duration import DEFAULT_OVERHEADS, OverheadModel, estimate_duration
from nightcrew.robotic.tasks._moving import MovingTarget
from nightcrew.robotic.tasks._request import ObservationType
from nightcrew.robotic.tasks._task import Task
from nightcrew.robotic.tasks.calibration import NOTHING_LEFT_S, calibration_block
from nightcrew.site import Site

__all__ = ["EARLY_START_WEIGHTS", "NOTHING_LEFT_S", "BlockConversion", "block_of", "blocks_of", "every_block"]

#: The share of a block's value an early start adds (see ``SchedulableBlock.early_start_weight``):
#: small, so urgency orders a block's own start without outweighing other requests' priorities.
EARLY_START_WEIGHTS = {
    ObservationType.NORMAL: 0.0,
    ObservationType.TIME_CRITICAL: 0.2,
    ObservationType.RAPID_RESPONSE: 0.5,
}


def block_of(
    task: Task, overheads: OverheadModel = DEFAULT_OVERHEADS, *, site: Site | None = None
) -> SchedulableBlock | None:
    """The block for ``task``, or None if none of its configurations has a target (or its target
    moves and no ``site`` is given: a moving target's position depends on where it is seen from)."""
    configurations = task.request.configurations
    target = next((c.target for c in configurations if c.target is not None), None)
    if target is None:
        return None
    if isinstance(target, MovingTarget):
        if site is None:
            return None
        first = task.request.windows[0]
        reference = (first.start.timestamp() + first.end.timestamp()) / 2.0
        scheduled: Target = EphemerisTarget.at(target.body(), site, reference)
    else:
        scheduled = Target(
            ra=target.ra,
            dec=target.dec,
            pm_ra_cosdec=target.proper_motion_ra,
            pm_dec=target.proper_motion_dec,
            epoch=target.epoch,
        )
    limits = [c.constraints for c in configurations]
    estimate = estimate_duration(task.request, overheads, progress=task.status.progress)
    return SchedulableBlock(
        id=task.id,
        priority=task.effective_priority,
        duration_s=max(sum(estimate.configurations_s), NOTHING_LEFT_S),
        target=scheduled,
        constraints=Constraints(
            max_airmass=min(c.max_airmass for c in limits),
            max_sun_altitude=min(c.max_sun_altitude for c in limits),
            min_moon_distance=max(c.min_lunar_distance for c in limits),
            max_moon_illumination=min(c.max_lunar_phase for c in limits),
        ),
        windows=tuple((window.start, window.end) for window in task.request.windows),
        setup_s=estimate.setup_s,
        early_start_weight=EARLY_START_WEIGHTS[task.observation_type],
    )


@dataclass(frozen=True)
class BlockConversion:
    """Blocks for the tasks that have one, and the ids of those that have none."""

    blocks: tuple[SchedulableBlock, ...]
    left_out: tuple[str, ...]


def blocks_of(tasks: Iterable[Task], overheads: OverheadModel = DEFAULT_OVERHEADS) -> BlockConversion:
    """Blocks for ``tasks`` (in order), with the ids of the tasks left out."""
    blocks: list[SchedulableBlock] = []
    left_out: list[str] = []
    for task in tasks:
        block = block_of(task, overheads)
        if block is None:
            left_out.append(task.id)
        else:
            blocks.append(block)
    return BlockConversion(tuple(blocks), tuple(left_out))


def every_block(
    tasks: Iterable[Task],
    site: Site | None,
    *,
    fit: GridFit | None = None,
    overheads: OverheadModel = DEFAULT_OVERHEADS,
) -> list[SchedulableBlock]:
    """A block for every task of ``tasks`` (in order): by :func:`block_of`, else a calibration block."""
    blocks = []
    for task in tasks:
        block = block_of(task, overheads, site=site)
        if block is None:
            block = calibration_block(task, site, fit=fit, overheads=overheads)
        blocks.append(block)
    return blocks
