"""Who drives: the robotic mode, or an INDI client (IndiServer's ``robotic`` option).

The rule: the first request of an INDI client to a device (any ``new*Vector`` naming a served
property) stops the robotic mode. The robotic module then does what it always does when stopped:
it ends its task, closes the roof and parks. The request waits for that - until the robotic module
reports no task and the served telescope and dome are parked - and then runs. From then on the
clients drive. When the last client that sent a request disconnects, the robotic mode is started
again (if it was running when the client took over). A robotic module that cannot be stopped, or
does not hand over within ``handover_timeout`` wall seconds, refuses the request (Alert with the
reason): nothing moves while two drivers could.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from typing import Any

from nightcrew.errors import ModuleError, NightcrewError
from nightcrew.interfaces import IMotion, IRobotic, IStartStop, MotionStatus

__all__ = ["ManualMode"]

log = logging.getLogger(__name__)

#: Wall seconds between two looks at whether the robotic module has handed over.
_LOOK = 0.2


class ManualMode:
    """Hands the observatory from the robotic module to INDI clients and back.

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
        self._drivers: set[object] = set()  # the connected clients that sent a request
        self._resume = False  # whether robotic mode ran when the clients took over
        self._lock = asyncio.Lock()

    @property
    def manual(self) -> bool:
        return bool(self._drivers)

    async def take(self, client: object, who: str) -> None:
        """Make ``client`` one of the drivers, stopping the robotic mode first if it runs.

        Raises:
            ModuleError: the robotic module cannot be stopped or does not hand over in time.
        """
        async with self._lock:
            if self._drivers:
                self._drivers.add(client)
                return
            robotic = await self._proxy(self.robotic, IStartStop)
            running = await robotic.is_running()
            if running:
                log.info("INDI client %s drives: stopping the robotic mode of %s", who, self.robotic)
                self._announce(f"robotic mode of {self.robotic} stopped: an INDI client drives now")
                await robotic.stop()
                await self._wait_for_handover(robotic)
            self._resume = self._resume or running
            self._drivers.add(client)

    async def _wait_for_handover(self, robotic: Any) -> None:
        motions = [await self._proxy(name, IMotion) for name in self._parked]
        try:
            async with asyncio.timeout(self._timeout):
                while True:
                    idle = (
                        not isinstance(robotic, IRobotic) or (await robotic.get_robotic_status()).task is None
                    )
                    statuses = [await m.get_motion_status() for m in motions]
                    if idle and all(s is MotionStatus.PARKED for s in statuses):
                        return
                    await asyncio.sleep(_LOOK)
        except TimeoutError:
            raise ModuleError(
                f"the robotic mode of {self.robotic} did not hand over (end its task, park "
                f"{', '.join(self._parked)}) within {self._timeout:g} s"
            ) from None

    async def release(self, client: object) -> None:
        """``client`` disconnected; the last driver gone, robotic mode starts again if it ran."""
        async with self._lock:
            if client not in self._drivers:
                return
            self._drivers.discard(client)
            if self._drivers or not self._resume:
                return
            self._resume = False
            try:
                robotic = await self._proxy(self.robotic, IStartStop)
                await robotic.start()
                log.info(
                    "the last INDI client that drove left: robotic mode of %s started again", self.robotic
                )
            except NightcrewError as exc:
                log.error("cannot start the robotic mode of %s again: %s", self.robotic, exc)
