"""Which device modules are away, and waiting (within a bound) for them to be back and ready.

The mastermind asks this after a device failed under a task (see
:func:`nightcrew.robotic.mastermind.device_fault`): a module the supervisor restarts, or one whose
device server restarts, is usually back within seconds, and the task can go on.
"""

from __future__ import annotations

import logging

from nightcrew.errors import NightcrewError
from nightcrew.events import ModuleClosedEvent, ModuleOpenedEvent
from nightcrew.interfaces import IModule, ModuleState
from nightcrew.object import Object

__all__ = ["DeviceWatch"]

log = logging.getLogger(__name__)

#: Clock seconds between two looks at a module that is not back yet.
_LOOK_INTERVAL = 1.0


class DeviceWatch:
    """Keeps the names of the modules that went offline and waits for modules to be READY.

    Args:
        host: The module whose comm and clock are used.
    """

    def __init__(self, host: Object) -> None:
        self._host = host
        self._away: set[str] = set()

    async def open(self) -> None:
        """Start listening to modules going and coming (after the host's comm is open)."""
        await self._host.comm.register_event(ModuleClosedEvent, self.on_module_closed)
        await self._host.comm.register_event(ModuleOpenedEvent, self.on_module_opened)

    @property
    def away(self) -> frozenset[str]:
        """The modules that went offline and have not come back."""
        return frozenset(self._away)

    async def on_module_closed(self, event: ModuleClosedEvent, sender: str) -> None:
        self._away.add(sender)

    async def on_module_opened(self, event: ModuleOpenedEvent, sender: str) -> None:
        self._away.discard(sender)

    async def wait_back(self, module: str | None, within: float) -> bool:
        """Wait up to ``within`` clock seconds until ``module`` - or, when the failure named none,
        every module that went offline and has not come back - is online and READY."""
        names = {module} if module is not None else set(self._away)
        if not names:
            return True
        waiting = ", ".join(sorted(names))
        log.info("%s: waiting up to %.0f s for %s to be back", self._host.context_name, within, waiting)
        clock = self._host.clock
        deadline = clock.time() + within
        while True:  # bounded by the deadline
            if all([await self._ready(name) for name in names]):
                log.info("%s: %s back", self._host.context_name, waiting)
                return True
            left = deadline - clock.time()
            if left <= 0:
                log.warning("%s: %s not back within %.0f s", self._host.context_name, waiting, within)
                return False
            await clock.sleep(min(_LOOK_INTERVAL, left))

    async def _ready(self, name: str) -> bool:
        if name not in self._host.comm.clients:
            return False
        try:
            return await (await self._host.proxy(name, IModule)).get_state() is ModuleState.READY
        except NightcrewError:
            return False
