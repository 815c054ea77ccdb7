"""Who drives: the robotic mode, or an INDI client (IndiServer's ``robotic`` option).

The rule: a request of an INDI client to a device (any ``new*Vector`` naming a served property)
while the robotic mode runs stops the robotic mode. The robotic module then does what it always
does when stopped: it ends its task, closes the roof and parks. The request waits for that - until
the robotic module reports ``stopped`` (not ``stopping``) without a task and the served telescope
and dome are parked - and then runs.
From then on the clients drive, one request or one connection after another (indi_setprop connects
once per request), and the robotic mode stays off until an operator starts it again (the web
console's *Start robotic mode*, or ``start`` of the mastermind over the comm); the next request of
an INDI client then stops it again. A robotic module that cannot be stopped, or does not hand over
within ``handover_timeout`` wall seconds, refuses the request (Alert with the reason): nothing
moves while two drivers could.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from typing import Any

from nightcrew.errors import ModuleError
from nightcrew.interfaces import IMotion, IRobotic, IStartStop, MotionStatus

__all__ = ["ManualMode"]

log = logging.getLogger(__name__)

#: Wall seconds between two looks at whether the robotic module has handed over.
_LOOK = 0.2


class ManualMode:
    """Hands the observatory from the robotic module to INDI clients.

    Args:
        robotic: Name of the IStartStop module (the mastermind).
        proxy: The server's proxy maker, ``proxy(name, interface)``.
        parked: Names of the served modules that must be parked before clients drive.
        handover_timeout: Wall seconds the robotic module gets to end its task and park.
        announce: Sends a message to every INDI client.
    """

    def __init__(
        self,
        robotic: str,
        proxy: Callable[[str, Any], Awaitable[Any]],
        parked: list[str],
        handover_timeout: float,
        announce: Callable[[str], None],
    ) -> None:
        self.robotic = robotic
        self._proxy = proxy
        self._parked = parked
        self._timeout = handover_timeout
        self._announce = announce
        self._lock = asyncio.Lock()

    async def take(self, who: str) -> None:
        """Stop the robotic mode if it runs and wait until it has handed over; then clients drive.

        Raises:
            NightcrewError: the robotic module cannot be reached or stopped, or does not hand over in time.
        """
        async with self._lock:  # one handover at a time; later requests find robotic mode off
            robotic = await self._proxy(self.robotic, IStartStop)
            if not await robotic.is_running():
                return
            log.info("INDI client %s drives: stopping the robotic mode of %s", who, self.robotic)
            self._announce(f"robotic mode of {self.robotic} stopped: INDI clients drive now")
            await robotic.stop()
            await self._wait_for_handover(robotic)
            log.info("the robotic mode of %s handed over to INDI clients", self.robotic)

    async def _wait_for_handover(self, robotic: Any) -> None:
        motions = [await self._proxy(name, IMotion) for name in self._parked]
        try:
            async with asyncio.timeout(self._timeout):
                while True:
                    idle = True
                    if isinstance(robotic, IRobotic):  # "stopped": no task, and closed and parked since
                        status = await robotic.get_robotic_status()
                        idle = status.action == "stopped" and status.task is None
                    statuses = [await m.get_motion_status() for m in motions]
                    if idle and all(s is MotionStatus.PARKED for s in statuses):
                        return
                    await asyncio.sleep(_LOOK)
        except TimeoutError:
            raise ModuleError(
                f"the robotic mode of {self.robotic} did not hand over (end its task, park "
                f"{', '.join(self._parked)}) within {self._timeout:g} s"
            ) from None
