"""Which device modules are away, and waiting (within a bound) for them to be back and ready.

The mastermind asks this after a device failed under a task (see
:func:`nightcrew.robotic.mastermind.device_fault`): a module the supervisor restarts, or one whose
device server restarts, is usually back within seconds, and the task can go on.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from nightcrew.errors import NightcrewError
from nightcrew.events import ModuleClosedEvent, ModuleOpenedEvent
from nightcrew.interfaces import ICamera, IModule, ModuleState
from nightcrew.object import Object

__all__ = ["DeviceWatch"]

log = logging.getLogger(__name__)

#: Clock seconds between two looks at a module that is not back yet.
_LOOK_INTERVAL = 1.0


class DeviceWatch:
    """Keeps the names of the modules that went offline and waits for modules to be READY.

    Args:
        host: The module whose comm and clock are used.
        on_return: Called when a module that went offline comes back (a restart).
    """

    def __init__(self, host: Object, on_return: Callable[[], None] | None = None) -> None:
        self._host, self._on_return = host, on_return
        self._away: set[str] = set()
        self._returns: dict[str, int] = {}  # module -> how often it came back (one entry a module)

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
        if sender in self._away:
            self._away.discard(sender)
            self._returns[sender] = self._returns.get(sender, 0) + 1
            if self._on_return is not None:
                self._on_return()

    def returns(self) -> dict[str, int]:
        """How often each module came back so far (compare two of these: who restarted between)."""
        return dict(self._returns)

    async def restarted_camera(self, since: dict[str, int]) -> str | None:
        """A camera module that came back since ``since`` (see :meth:`returns`), or None.

        A restarted camera module starts from its defaults (exposure time, binning, window): what a
        running task set up there is gone, so the task must set it up again.
        """
        for name, count in self._returns.items():
            if count > since.get(name, 0):
                try:
                    if ICamera.__name__ in await self._host.comm.get_interface_names(name):
                        return name
                except NightcrewError:
                    continue  # gone again: its next call fails, a device fault
        return None

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
