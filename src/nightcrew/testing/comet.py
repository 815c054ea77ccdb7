"""A local VOEvent broker for tests: Comet (``twistd -n comet --receive --broadcast``) on loopback
ports, and an author's side of the VOEvent Transport Protocol to publish notices to it.

Comet binds its ports on every interface; its author and subscriber whitelists admit only
127.0.0.1, so nothing else can publish or listen.
"""

from __future__ import annotations

import asyncio
import struct
import sys
from pathlib import Path

from lxml import etree  # type: ignore[import-untyped]

from nightcrew.testing.processes import ChildServer, free_port, wait_until_listening

__all__ = ["CometBroker"]

_LENGTH = struct.Struct("!I")  # a VTP packet: 4-byte big-endian length, then the XML


class CometBroker(ChildServer):
    """Comet receiving notices on ``receive_port`` and broadcasting them on ``port``.

    Args:
        directory: For its event database and log.
    """

    def __init__(self, directory: Path) -> None:
        super().__init__(directory)
        self.receive_port = free_port()

    @property
    def address(self) -> str:
        """``host:port`` subscribers connect to."""
        return f"{self.host}:{self.port}"

    def start(self) -> None:
        """Start Comet; return once both ports listen."""
        twistd = Path(sys.executable).with_name("twistd")
        command = [
            str(twistd),
            "-n",
            "--pidfile=",
            "comet",
            "--receive",
            "--broadcast",
            f"--receive-port={self.receive_port}",
            f"--broadcast-port={self.port}",
            "--local-ivo=ivo://nightcrew.test/comet",
            f"--eventdb={self.directory}",
            "--broadcast-test-interval=0",
            "--author-whitelist=127.0.0.1/32",
            "--subscriber-whitelist=127.0.0.1/32",
        ]
        log = self.directory / "comet.log"
        self._spawn(command, what="comet", log=log)
        assert self._process is not None
        wait_until_listening(self._process, self.receive_port, what="comet (receiving)", log=log)

    async def publish(self, payload: bytes) -> str:
        """Send ``payload`` as an author and return the broker's answer: ``ack``, ``nak``, or
        ``closed`` when it dropped the connection without one (a packet it cannot parse); within
        10 wall seconds."""
        async with asyncio.timeout(10.0):
            reader, writer = await asyncio.open_connection(self.host, self.receive_port)
            try:
                writer.write(_LENGTH.pack(len(payload)) + payload)
                await writer.drain()
                try:
                    (length,) = _LENGTH.unpack(await reader.readexactly(_LENGTH.size))
                    answer = etree.fromstring(await reader.readexactly(length))
                except asyncio.IncompleteReadError:
                    return "closed"
            finally:
                writer.close()
                await writer.wait_closed()
        return str(answer.get("role"))
