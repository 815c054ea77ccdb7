"""Robotic operation modules: the scheduler and the mastermind."""

from nightcrew.modules.robotic.mastermind import Mastermind
from nightcrew.modules.robotic.scheduler import SchedulerModule

__all__ = ["Mastermind", "SchedulerModule"]
