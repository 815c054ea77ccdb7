"""The robotic layer: autonomous operation, running scripts on request, and what the night looks like
(the mastermind's status, the scheduler's plan) for displays such as the web console."""

from __future__ import annotations

from abc import abstractmethod
from dataclasses import dataclass
from datetime import datetime

from nightcrew.interfaces.base import Interface
from nightcrew.timeout import timeout

__all__ = [
    "IAutonomous",
    "IRobotic",
    "IRoboticScheduler",
    "IScriptRunner",
    "Plan",
    "PlannedTask",
    "RoboticStatus",
    "RoboticTask",
    "UnplannedTask",
]


class IAutonomous(Interface):
    """A module that may act on its own (mastermind, scheduler); others yield to it."""

    @abstractmethod
    async def is_autonomous(self) -> bool:
        """Whether the module is currently acting on its own."""


class IScriptRunner(Interface):
    """Runs observing scripts given as text."""

    @timeout(3600)
    @abstractmethod
    async def run_script(self, script: str) -> None:
        """Run ``script`` (the YAML configuration of a script) and return when it ends."""


@dataclass(frozen=True)
class RoboticTask:
    """The task a robotic module is running, and how far it got."""

    id: str
    name: str
    started: datetime | None  # clock time it started
    eta: datetime | None  # expected end (the end of its slot)
    exposures_done: int
    exposures_total: int


@dataclass(frozen=True)
class RoboticStatus:
    """What a robotic module (the mastermind) is doing now, and why.

    ``action`` is one of ``run_task``, ``open_up``, ``focus``, ``close_and_park``, ``wait``,
    ``stopping`` (robotic mode is off and the roof not yet closed or the telescope not yet parked
    since) or ``stopped``; ``waiting_for`` says why it waits (None unless ``wait``). The conditions
    are those of its last look at the world (None before the first).
    """

    time: datetime
    running: bool
    action: str
    description: str
    waiting_for: str | None = None
    waiting_until: datetime | None = None
    task: RoboticTask | None = None
    sun_altitude: float | None = None
    weather_good: bool | None = None
    roof: str | None = None
    telescope_ready: bool | None = None


class IRobotic(Interface):
    """A module running the night on its own, which can say what it does and why."""

    @abstractmethod
    async def get_robotic_status(self) -> RoboticStatus:
        """The current action, the running task with its progress, the reason for waiting."""


@dataclass(frozen=True)
class PlannedTask:
    """One task placed in a plan; ``name`` when the planner knows it."""

    task_id: str
    start: datetime
    end: datetime
    priority: float | None = None
    name: str | None = None


@dataclass(frozen=True)
class UnplannedTask:
    """A task the plan leaves out, and why (for a person: the constraint that keeps it out)."""

    task_id: str
    reason: str
    name: str | None = None


@dataclass(frozen=True)
class Plan:
    """A scheduler's latest plan of the night, with the solver's objective and proven bound."""

    planned_at: datetime
    night_start: datetime
    night_end: datetime
    solver: str
    status: str
    objective: float
    bound: float | None
    gap: float | None
    wall_time_s: float
    slots: tuple[PlannedTask, ...]
    unplanned: tuple[UnplannedTask, ...] = ()


class IRoboticScheduler(Interface):
    """A module planning the night, which can show its plan."""

    @abstractmethod
    async def get_plan(self) -> Plan | None:
        """The latest plan; None before the first."""
