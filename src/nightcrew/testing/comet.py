"""A local VOEvent broker for tests: Comet (``twistd -n comet --receive --broadcast``) in a network
namespace of its own, and an author's side of the VOEvent Transport Protocol to publish notices to
it.

Comet binds its ports on every interface and has no option to choose one, so, like indiserver, it
runs only inside a :class:`~nightcrew.testing.indi.PrivateNetwork`, reached from the test through
the namespace's veth link; its author and subscriber whitelists admit only that link.
"""

from __future__ import annotations

import asyncio
import struct
import sys
from pathlib import Path

from lxml import etree  # type: ignore[import-untyped]

from nightcrew.testing.indi import PrivateNetwork
from nightcrew.testing.processes import ChildServer, wait_until_listening

__all__ = ["CometBroker"]

_LENGTH = struct.Struct("!I")  # a VTP packet: 4-byte big-endian length, then the XML


class CometBroker(ChildServer):
    """Comet receiving notices on ``receive_port`` and broadcasting them on ``port``.

    Args:
        directory: For its event database and log.
    """

    #: Comet's own default ports: the namespace holds nothing else.
    RECEIVE_PORT = 8098
    BROADCAST_PORT = 8099

    def __init__(self, directory: Path) -> None:
        self.network = PrivateNetwork()
        # The namespace's address is known once it exists (start).
        super().__init__(directory, host="", port=self.BROADCAST_PORT, wrap=self.network.command)
        self.receive_port = self.RECEIVE_PORT

    @property
    def address(self) -> str:
        """``host:port`` subscribers connect to."""
        return f"{self.host}:{self.port}"

    def start(self) -> None:
        """Start the namespace and Comet in it; return once both ports listen."""
        self.network.start()
        self.host = self.network.host
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
            f"--author-whitelist={self.network.test_address}/32",
            f"--subscriber-whitelist={self.network.test_address}/32",
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

    def stop(self) -> None:
        """Stop Comet, then end its namespace; safe to call twice."""
        super().stop()
        self.network.stop()
