"""The task runner: picks a script for each configuration of a task and runs them in order."""

from __future__ import annotations

import logging
from typing import Any

from nightcrew.config import build_object
from nightcrew.errors import ConfigError, NotSupportedError
from nightcrew.object import Object
from nightcrew.robotic.runner._narrow import configuration_task, merged_progress
from nightcrew.robotic.runner._script import ProgressCallback, Script
from nightcrew.robotic.tasks import Configuration, ConfigurationType, Task, TaskProgress

__all__ = ["SCRIPT_PREFIX", "TaskRunner", "script_key"]

log = logging.getLogger(__name__)

#: Scripts for SCRIPT configurations are configured under ``SCRIPT:<extra_params.script>``.
SCRIPT_PREFIX = f"{ConfigurationType.SCRIPT.value}:"


def script_key(configuration: Configuration) -> str:
    """The key of ``scripts`` that runs ``configuration``: its type, or ``SCRIPT:<name>``."""
    if configuration.type is ConfigurationType.SCRIPT:
        return SCRIPT_PREFIX + str(configuration.extra_params.get("script", "")).strip()
    return configuration.type.value


class TaskRunner(Object):
    """Runs tasks: each configuration by the script configured for its type, in order.

    Added as a child by the mastermind, so the scripts get its comm and clock::

        runner:
          class: nightcrew.robotic.runner.TaskRunner
          scripts:
            EXPOSE: {class: nightcrew.robotic.scripts.ImagingScript, camera: camera}
            SCRIPT:pointing: {class: nightcrew.robotic.scripts.PointingSeriesScript}

    Args:
        scripts: Configuration type name (``EXPOSE``, ``BIAS``, ...) or ``SCRIPT:<name>`` (for
            SCRIPT configurations whose ``extra_params.script`` is ``<name>``) to a script or its
            description.
    """

    def __init__(self, *, scripts: dict[str, Script | dict[str, Any]], **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._scripts: dict[str, Script] = {}
        for key, value in scripts.items():
            _check_key(key)
            script = value if isinstance(value, Script) else build_object(value, Script)
            if not isinstance(script, Script):
                raise ConfigError(f"expected a Script, got {type(script).__name__}", key=f"scripts.{key}")
            self._scripts[key] = script
        self._adopted = False

    @property
    def scripts(self) -> dict[str, Script]:
        """The configured scripts by key (a copy)."""
        return dict(self._scripts)

    def _adopt_scripts(self) -> None:
        # Scripts share the runner's context, which the runner itself may only get when the
        # mastermind adds it (after this constructor): so adopt them once the context is there.
        if self._adopted or self._comm is None:
            return
        self._adopted = True
        unique = {id(script): script for script in self._scripts.values()}
        for script in unique.values():
            self.add_child(script)

    async def open(self) -> None:
        self._adopt_scripts()
        await super().open()

    def script_for(self, task: Task) -> Script:
        """The script for the task's first configuration (see :meth:`script_for_configuration`)."""
        return self.script_for_configuration(task.request.configurations[0])

    def script_for_configuration(self, configuration: Configuration) -> Script:
        """The script configured for ``configuration``'s type (or ``SCRIPT:<name>``).

        Raises:
            NotSupportedError: None is configured; the message names the type.
        """
        self._adopt_scripts()
        key = script_key(configuration)
        script = self._scripts.get(key)
        if script is None:
            configured = ", ".join(sorted(self._scripts)) or "none"
            raise NotSupportedError(
                f"no script configured for {key} configurations (configured: {configured})"
            )
        return script

    async def can_run(self, task: Task) -> bool:
        """Whether every configuration has a script that can run it now."""
        for index, configuration in enumerate(task.request.configurations):
            try:
                script = self.script_for_configuration(configuration)
            except NotSupportedError as exc:
                log.info("task %s cannot run: %s", task.id, exc)
                return False
            if not await script.can_run(configuration_task(task, index)):
                log.info("task %s: %s cannot run configuration %d now", task.id, type(script).__name__, index)
                return False
        return True

    async def run_task(self, task: Task, progress: ProgressCallback) -> None:
        """Run the task's configurations in order, each by its script; report the whole task's progress.

        Progress recorded in ``task`` (an interrupted earlier attempt) counts: only what is missing
        is taken, and the reports start from it.

        Raises:
            NotSupportedError: A configuration has no script (checked before anything moves).
            NightcrewError: A script failed; later configurations do not run.
            asyncio.CancelledError: Aborted (the running script has cleaned up).
        """
        scripts = [self.script_for_configuration(c) for c in task.request.configurations]
        # A retried task goes on from its recorded progress: finished configurations are skipped
        # and the scripts take only the exposures still missing.
        done = task.status.progress.or_nothing(task.request)
        for index, script in enumerate(scripts):
            if done.nothing_left(task.request, index):
                log.info("task %s: configuration %d was done in an earlier attempt", task.id, index + 1)
                continue

            async def report(part: TaskProgress, index: int = index) -> None:
                nonlocal done
                done = merged_progress(done, index, part)
                await progress(done)

            log.info(
                "task %s: configuration %d/%d (%s) by %s",
                task.id,
                index + 1,
                len(scripts),
                task.request.configurations[index].type.value,
                type(script).__name__,
            )
            await script.run(configuration_task(task, index), report)


def _check_key(key: str) -> None:
    if key.startswith(SCRIPT_PREFIX):
        if not key[len(SCRIPT_PREFIX) :].strip():
            raise ConfigError("a SCRIPT key needs a name: SCRIPT:<name>", key=f"scripts.{key}")
        return
    if key not in ConfigurationType.__members__ or key == ConfigurationType.SCRIPT.value:
        names = ", ".join(t.value for t in ConfigurationType if t is not ConfigurationType.SCRIPT)
        raise ConfigError(
            f"unknown configuration type; use one of {names} or SCRIPT:<name>", key=f"scripts.{key}"
        )
