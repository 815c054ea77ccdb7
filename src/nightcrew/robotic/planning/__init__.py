"""The one shape of a planned task: :class:`PlannedSlot`, from the scheduler to the mastermind.

The scheduler places the requests it is given (its
:class:`~nightcrew.robotic.scheduler.SchedulableBlock`: what to observe, not yet planned) as
planned slots; a schedule store of :mod:`nightcrew.robotic.archives` keeps them as they are; the
mastermind reads them back and decides on each together with what its task needs (its
:class:`~nightcrew.robotic.mastermind.Slot` holds the planned slot, it does not copy it). Nothing
converts one into another on the way.

The package imports nothing of the robotic layer, so that scheduler, archives and mastermind all
name the same type (the import-linter contracts in pyproject.toml keep it so).
"""

from nightcrew.robotic.planning._slot import PlannedSlot

__all__ = ["PlannedSlot"]
