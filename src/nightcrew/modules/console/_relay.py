"""Live messages to the browsers: one bounded queue per WebSocket, so a slow browser never blocks.

A message is serialised once and offered to every client's queue; a full queue drops the message
for that client and counts it, and the client is told the count (a ``dropped`` message) as soon as
its queue has room again. The module never awaits a browser.
"""

from __future__ import annotations

import asyncio
import json
from collections.abc import Awaitable, Callable
from typing import Any

__all__ = ["Client", "Relay"]

#: Messages a client may lag behind before new ones are dropped for it.
QUEUE_SIZE = 1000


class Client:
    """One connected browser: its queue, what was dropped for it, and the session it belongs to."""

    def __init__(self, session_token: str, size: int = QUEUE_SIZE) -> None:
        self.session_token = session_token
        self.dropped = 0
        self._queue: asyncio.Queue[str] = asyncio.Queue(size)
        self._size = size
        self._owe_notice = False

    def offer(self, text: str) -> None:
        try:
            self._queue.put_nowait(text)
        except asyncio.QueueFull:
            self.dropped += 1
            self._owe_notice = True

    async def pump(self, send: Callable[[str], Awaitable[None]]) -> None:
        """Send queued messages with ``send`` until cancelled or ``send`` fails."""
        while True:
            await send(await self._queue.get())
            if self._owe_notice and self._queue.qsize() < self._size // 2:
                self._owe_notice = False
                await send(json.dumps({"type": "dropped", "count": self.dropped}))


class Relay:
    """The connected clients; :meth:`send` offers a message to each."""

    def __init__(self) -> None:
        self._clients: set[Client] = set()
        self._dropped_by_gone = 0

    @property
    def dropped_total(self) -> int:
        """Messages dropped for any client since the console started."""
        return self._dropped_by_gone + sum(c.dropped for c in self._clients)

    @property
    def clients(self) -> set[Client]:
        return set(self._clients)

    def add(self, client: Client) -> None:
        self._clients.add(client)

    def remove(self, client: Client) -> None:
        if client in self._clients:
            self._clients.discard(client)
            self._dropped_by_gone += client.dropped

    def send(self, message: dict[str, Any]) -> None:
        if not self._clients:
            return
        text = json.dumps(message, ensure_ascii=False)
        for client in self._clients:
            client.offer(text)
