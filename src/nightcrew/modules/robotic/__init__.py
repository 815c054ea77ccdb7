"""Robotic operation modules: the scheduler (more to come: mastermind)."""

from nightcrew.modules.robotic.scheduler import SchedulerModule

__all__ = ["SchedulerModule"]
