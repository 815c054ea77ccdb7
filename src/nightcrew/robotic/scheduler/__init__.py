"""Night scheduling: which block to observe when, optimally (MIP) or greedily (astroplan).

The pieces, each usable alone: :mod:`.blocks` (input and output values), :mod:`.sky` and
:mod:`.constraints` (where each block is observable on a time grid), :mod:`.problem` (the grid form
shared by the solvers), :mod:`.mip` (the optimal solver), :mod:`.baseline` (astroplan's
PriorityScheduler) and :class:`Scheduler`, which ties them together and re-plans.
"""

from nightcrew.robotic.scheduler.blocks import (
    Constraints,
    Night,
    SchedulableBlock,
    Schedule,
    Target,
)
from nightcrew.robotic.scheduler.constraints import (
    DEFAULT_CONSTRAINTS,
    AirmassConstraint,
    Constraint,
    MoonDistanceConstraint,
    MoonIlluminationConstraint,
    SunAltitudeConstraint,
    WindowConstraint,
    visibility,
)
from nightcrew.robotic.scheduler.problem import Placement, SchedulingProblem, build_problem
from nightcrew.robotic.scheduler.scheduler import SOLVERS, Scheduler
from nightcrew.robotic.scheduler.sky import SkyGrid, TimeGrid

__all__ = [
    "DEFAULT_CONSTRAINTS",
    "SOLVERS",
    "AirmassConstraint",
    "Constraint",
    "Constraints",
    "MoonDistanceConstraint",
    "MoonIlluminationConstraint",
    "Night",
    "Placement",
    "SchedulableBlock",
    "Schedule",
    "Scheduler",
    "SchedulingProblem",
    "SkyGrid",
    "SunAltitudeConstraint",
    "Target",
    "TimeGrid",
    "WindowConstraint",
    "build_problem",
    "visibility",
]
