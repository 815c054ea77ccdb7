"""The supervisor on the bus: a module whose state is the supervisor's heartbeat.

With ``nightcrew up DIR --comm FILE`` (FILE describes a comm, like ``operator.yaml``) the supervisor
joins the modules' room as a module of its own (named after the comm, e.g. ``supervisor``). It is
READY while every module it supervises runs or restarts, and in ERROR, naming them, while one is
``failed``, ``broken`` or ``frozen`` (until it is restarted): the safety watchdog, watching it like
the weather module, then closes the roof. If the supervisor itself hangs or dies, it stops
answering, which the watchdog also sees.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from pathlib import Path

from nightcrew.comm.base import Comm
from nightcrew.config import build_object, load_config
from nightcrew.supervisor._process import ModuleStatus

__all__ = ["SupervisorPresence"]

_BAD_STATES = ("failed", "broken", "frozen")
_CHECK_INTERVAL = 1.0  # wall seconds between two looks at the modules' states


class SupervisorPresence:
    """Keeps a module on ``comm_file``'s comm whose state mirrors the supervised modules."""

    def __init__(self, comm_file: Path, statuses: Callable[[], list[ModuleStatus]]) -> None:
        from nightcrew.modules import Module

        self._module = Module(comm=build_object(load_config(comm_file), Comm))
        self._statuses = statuses
        self._task: asyncio.Task[None] | None = None

    async def open(self) -> None:
        await self._module.open()
        self._task = asyncio.get_running_loop().create_task(self._mirror_loop())

    async def close(self) -> None:
        if self._task is not None:
            self._task.cancel()
            await asyncio.gather(self._task, return_exceptions=True)
        await self._module.close()

    async def _mirror_loop(self) -> None:
        while True:
            bad = [f"{s.name} {s.state}: {s.error}" for s in self._statuses() if s.state in _BAD_STATES]
            if bad:
                self._module.set_error("; ".join(bad))
            else:
                await self._module.reset_error()
            await asyncio.sleep(_CHECK_INTERVAL)
