"""Nobody locks the INDI server's other clients out: limits per address, silent connections dropped.

The listener alone on a free loopback port, its clients raw TCP connections (what an attacker
opens); a legitimate client is one that starts, as every INDI client does, with getProperties.
"""

from __future__ import annotations

import asyncio
import contextlib
import xml.etree.ElementTree as ET
from collections.abc import AsyncIterator

from nightcrew.bridges.indi.server_listener import IndiClient, IndiListener
from nightcrew.testing.waiting import wait_for

GET_PROPERTIES = b'<getProperties version="1.7"/>\n'
Connection = tuple[asyncio.StreamReader, asyncio.StreamWriter]


class Heard:
    """The listener's handler: the tags every client sent, by its host."""

    def __init__(self) -> None:
        self.tags: list[tuple[str, str]] = []

    async def __call__(self, client: IndiClient, element: ET.Element) -> None:
        self.tags.append((client.host, element.tag))


@contextlib.asynccontextmanager
async def listening(
    *, max_clients: int = 16, max_clients_per_address: int = 4, idle_timeout: float = 60.0
) -> AsyncIterator[tuple[IndiListener, Heard]]:
    heard = Heard()
    listener = IndiListener(
        "127.0.0.1",
        0,
        heard,
        max_clients=max_clients,
        max_clients_per_address=max_clients_per_address,
        idle_timeout=idle_timeout,
    )
    await listener.start()
    try:
        yield listener, heard
    finally:
        await listener.close()


async def connect(listener: IndiListener, source: str = "127.0.0.1") -> Connection:
    return await asyncio.open_connection("127.0.0.1", listener.port, local_addr=(source, 0))


async def hung_up(connection: Connection) -> bool:
    """Whether the server closed ``connection`` (it sends nothing to a client that asked nothing)."""
    try:
        return await asyncio.wait_for(connection[0].read(1), 10) == b""
    except ConnectionResetError:
        return True


async def close_all(connections: list[Connection]) -> None:
    for _, writer in connections:
        writer.close()
        with contextlib.suppress(OSError):
            await writer.wait_closed()


async def test_sixteen_silent_connections_lock_nobody_out() -> None:
    async with listening() as (listener, heard):
        silent = [await connect(listener) for _ in range(16)]
        legitimate = await connect(listener)
        legitimate[1].write(GET_PROPERTIES)
        await wait_for(lambda: ("127.0.0.1", "getProperties") in heard.tags, 10)
        # The silent ones made room: the oldest were dropped, at most the address's limit is held.
        assert sum([await hung_up(c) for c in silent[:13]]) == 13
        assert len(listener.clients) <= 4
        await close_all([*silent, legitimate])


async def test_a_silent_or_trickling_client_is_dropped_one_that_spoke_may_listen() -> None:
    async with listening(idle_timeout=0.3) as (listener, heard):
        listening_client = await connect(listener)
        listening_client[1].write(GET_PROPERTIES)  # it spoke (heard): from now on it may be silent
        await wait_for(lambda: len(heard.tags) == 1, 10)
        silent, trickling = await connect(listener), await connect(listener)
        trickling[1].write(b"<getProperties")
        assert await hung_up(silent) and await hung_up(trickling)
        listening_client[1].write(b'<getProperties version="1.7" device="again"/>')
        await wait_for(lambda: heard.tags.count(("127.0.0.1", "getProperties")) == 2, 10)
        await close_all([silent, trickling, listening_client])


async def test_one_address_cannot_take_every_place() -> None:
    other = "127.0.0.2"  # another address of the loopback interface
    async with listening(max_clients=6) as (listener, heard):
        spoke = [await connect(listener) for _ in range(4)]
        for _, writer in spoke:
            writer.write(GET_PROPERTIES)
        await wait_for(lambda: len(heard.tags) == 4, 10)
        fifth = await connect(listener)
        assert await hung_up(fifth)  # every one of the address spoke: the new one is refused
        elsewhere = await connect(listener, other)
        elsewhere[1].write(GET_PROPERTIES)
        await wait_for(lambda: (other, "getProperties") in heard.tags, 10)
        await close_all([*spoke, fifth, elsewhere])
