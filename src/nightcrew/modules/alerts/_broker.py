"""A subscription to a VOEvent broker: pygcn's client in a child process, its events as callbacks.

pygcn's ``listen`` blocks for ever, so it runs in a child process (``_pygcn_child.py``, run by its
path) that this class starts, reads (one JSON line per VOEvent or log line) and stops by its PID.
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
import json
import logging
import sys
from collections.abc import Awaitable, Callable
from pathlib import Path

__all__ = ["BrokerSubscription"]

log = logging.getLogger(__name__)

_CHILD = Path(__file__).with_name("_pygcn_child.py")


class BrokerSubscription:
    """Receives the VOEvents a broker sends and hands each payload to ``on_voevent``.

    Args:
        host, port: The broker's VOEvent Transport Protocol address (its broadcast port).
        ivorn: How this client names itself in its replies.
        on_voevent: Called with each VOEvent's bytes, one at a time.
    """

    def __init__(
        self, host: str, port: int, ivorn: str, on_voevent: Callable[[bytes], Awaitable[None]]
    ) -> None:
        self._address, self._ivorn, self._on_voevent = (host, port), ivorn, on_voevent
        self._process: asyncio.subprocess.Process | None = None
        self._reader: asyncio.Task[None] | None = None
        self.connected = asyncio.Event()  # set while connected to the broker

    async def open(self) -> None:
        """Start the client (it connects, and reconnects, by itself)."""
        host, port = self._address
        self._process = await asyncio.create_subprocess_exec(
            sys.executable, str(_CHILD), host, str(port), self._ivorn, stdout=asyncio.subprocess.PIPE
        )
        self._reader = asyncio.create_task(self._read_loop(self._process), name="VOEvent broker")

    async def close(self) -> None:
        """Stop the client; safe to call twice."""
        process, reader = self._process, self._reader
        self._process = self._reader = None
        if process is not None and process.returncode is None:
            process.terminate()
            try:
                async with asyncio.timeout(5.0):
                    await process.wait()
            except TimeoutError:
                process.kill()
                await process.wait()
        if reader is not None:
            reader.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await reader
        self.connected.clear()

    async def _read_loop(self, process: asyncio.subprocess.Process) -> None:
        assert process.stdout is not None
        async for line in process.stdout:  # ends when the child does
            try:
                message = json.loads(line)
            except json.JSONDecodeError:
                log.warning("the VOEvent client wrote something unreadable: %r", line[:200])
                continue
            if "voevent" in message:
                try:
                    await self._on_voevent(base64.b64decode(message["voevent"]))
                except Exception as exc:  # one notice's trouble must not end the subscription
                    log.error("handling a VOEvent failed: %s", exc or type(exc).__name__)
            else:
                self._on_log(int(message.get("log", logging.INFO)), str(message.get("message", "")))
        if self._process is process:
            log.error("the VOEvent client stopped (exit code %s)", await process.wait())

    def _on_log(self, level: int, message: str) -> None:
        if message.startswith("connected to"):
            self.connected.set()
        elif message in ("closed socket", "timed out") or message.startswith("could not connect"):
            self.connected.clear()
        if message.endswith("unrecognized role: authenticate"):
            level = logging.DEBUG  # Comet offers authentication, which pygcn does not take: no matter
        if level >= logging.INFO:
            log.log(min(level, logging.WARNING), "broker %s:%d: %s", *self._address, message)
