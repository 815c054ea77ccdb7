"""XMPP pings (XEP-0199) that notice a dead link in seconds, not in TCP's minutes.

A link that goes silent (cable pulled, a router down) tells nobody: TCP keeps retransmitting with
a growing back-off, and a module learns of the loss only when TCP gives up, many minutes later.
With a ping to the server every ``interval`` wall seconds, an answer missing for ``timeout``
seconds ends the session at once (``on_dead``), so the connection's reconnect loop starts.
slixmpp's ``xep_0199`` plugin sends the pings and answers the server's; its own keepalive is not
used, because it reconnects by itself and would race the connection's reconnect loop.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable
from typing import Any

from slixmpp.exceptions import IqError, IqTimeout

__all__ = ["Keepalive"]

log = logging.getLogger(__name__)


class Keepalive:
    """One ping loop per session: :meth:`start` after a session starts, :meth:`stop` when it ends.

    Args:
        interval: Wall seconds between pings.
        timeout: Wall seconds a ping may go unanswered before the link counts as dead.
        on_dead: Called once with a reason when a ping goes unanswered.
    """

    def __init__(self, interval: float, timeout: float, on_dead: Callable[[str], None]) -> None:
        self._interval = interval
        self._timeout = timeout
        self._on_dead = on_dead
        self._task: asyncio.Task[None] | None = None

    def start(self, plugin: Any) -> None:
        """Ping through ``plugin`` (the client's ``xep_0199``) until :meth:`stop`."""
        self.stop()
        self._task = asyncio.get_running_loop().create_task(self._ping_loop(plugin))

    def stop(self) -> None:
        """End the loop (safe to call twice, and from inside ``on_dead``)."""
        task, self._task = self._task, None
        if task is not None and task is not asyncio.current_task():
            task.cancel()

    async def _ping_loop(self, plugin: Any) -> None:
        while True:
            await asyncio.sleep(self._interval)
            try:
                await plugin.ping(timeout=self._timeout)
            except IqTimeout:
                self._task = None
                self._on_dead(f"no answer to a ping within {self._timeout:g} s")
                return
            except IqError:
                continue  # an error reply is an answer: the link is alive
