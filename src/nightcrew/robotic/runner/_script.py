"""The base class of observing scripts, and what they share: progress reporting and device checks."""

from __future__ import annotations

import abc
from collections.abc import Awaitable, Callable
from typing import TypeVar, cast

from nightcrew.errors import InvalidArgumentError, NightcrewError
from nightcrew.interfaces import Interface
from nightcrew.object import Object
from nightcrew.robotic.tasks import Configuration, Task, TaskProgress

__all__ = ["ProgressCallback", "ProgressReporter", "Script", "ScriptError", "the_configuration"]

I = TypeVar("I", bound=Interface)  # noqa: E741 - the conventional name for an interface type

#: Called with the task's progress after every exposure (and after every series a module takes).
ProgressCallback = Callable[[TaskProgress], Awaitable[None]]


class ScriptError(NightcrewError):
    """A step of a script failed; the message names the step and the cause."""


class Script(Object, abc.ABC):
    """Runs one configuration of a task on the devices, which it reaches only through proxies.

    A script is handed a task holding exactly the configuration to run (the :class:`TaskRunner`
    narrows multi-configuration tasks; see :func:`the_configuration`). Module names are
    constructor parameters typed ``str | IThing``; the comm and clock come from the object that
    adds the script as a child (the runner).
    """

    @abc.abstractmethod
    async def can_run(self, task: Task) -> bool:
        """Whether the devices are there and the configuration is supported; fast, no side effects."""

    @abc.abstractmethod
    async def run(self, task: Task, progress: ProgressCallback) -> None:
        """Run the task's configuration, calling ``progress`` after every exposure.

        Raises:
            ScriptError: A step failed (the message says which and why).
            NightcrewError: The configuration cannot be run (e.g. NotSupportedError).
            asyncio.CancelledError: Aborted; devices were stopped before it propagates.
        """

    async def proxy_as(self, target: str | Interface, interface: type[I]) -> I:
        """A proxy for ``target`` (given as ``str | IThing``) checked for another ``interface``."""
        return await self.proxy(cast("str | I", target), interface)

    async def optional_proxy(self, target: str | Interface | None, interface: type[I]) -> I | None:
        """A proxy for ``target`` if it is there and offers ``interface``, else None."""
        if target is None or not await self.offers(target, interface):
            return None
        return await self.proxy_as(target, interface)

    async def offers(self, target: str | Interface | None, *interfaces: type[Interface]) -> bool:
        """Whether ``target`` (a module name or a local object) is there and offers ``interfaces``."""
        if target is None:
            return False
        if not isinstance(target, str):
            return all(isinstance(target, interface) for interface in interfaces)
        if target not in self.comm.clients:
            return False
        try:
            names = await self.comm.get_interface_names(target)
        except NightcrewError:
            return False  # it went offline while we asked
        return all(interface.__name__ in names for interface in interfaces)


def the_configuration(task: Task) -> Configuration:
    """The one configuration a script was handed.

    Raises:
        InvalidArgumentError: The task has several; those run through a TaskRunner.
    """
    configurations = task.request.configurations
    if len(configurations) != 1:
        raise InvalidArgumentError(
            f"task {task.id} has {len(configurations)} configurations; a script runs one "
            "(run the task through a TaskRunner)"
        )
    return configurations[0]


class ProgressReporter:
    """Counts the exposures of one script run and reports the task's progress after each (and
    after a frame cut short and kept).

    Counting starts from what the task has recorded (an earlier, interrupted attempt), so a script
    takes only :meth:`remaining` exposures and the reports never go back.
    """

    def __init__(self, task: Task, callback: ProgressCallback) -> None:
        self.request = task.request
        self._callback = callback
        self.progress = task.status.progress.or_nothing(task.request)

    def remaining(self, instrument_config: int) -> int:
        """Exposures of instrument config ``instrument_config`` still to take."""
        return self.progress.remaining(self.request, 0, instrument_config)

    async def add(self, instrument_config: int, count: int = 1) -> None:
        """``count`` more exposures of instrument config ``instrument_config`` are done."""
        self.progress = self.progress.with_exposures(self.request, 0, instrument_config, count)
        await self._callback(self.progress)

    async def add_cut_short(self, instrument_config: int, exposed: float) -> None:
        """A frame of instrument config ``instrument_config`` was stopped after ``exposed`` seconds
        and kept: recorded, but not an exposure done (its exposure time was not met)."""
        self.progress = self.progress.with_cut_short(self.request, 0, instrument_config, exposed)
        await self._callback(self.progress)
