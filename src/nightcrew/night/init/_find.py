"""All devices of the servers named for ``nightcrew init``: Alpaca (given or discovered) and INDI."""

from __future__ import annotations

from collections.abc import Iterable

from nightcrew.bridges.alpaca.discovery import DISCOVERY_PORT
from nightcrew.errors import NightcrewError
from nightcrew.night.init._alpaca import find_alpaca_devices
from nightcrew.night.init._found import FoundDevice
from nightcrew.night.init._indi import find_indi_devices
from nightcrew.night.init._options import parse_host_port

__all__ = ["find_devices"]


async def find_devices(
    alpaca: Iterable[str],
    indi: Iterable[str],
    *,
    alpaca_discovery: bool = False,
    address: str = "255.255.255.255",
    port: int = DISCOVERY_PORT,
) -> list[FoundDevice]:
    """The devices of the Alpaca servers ``alpaca`` (URLs; with none given and ``alpaca_discovery``,
    those answering UDP discovery at ``address``) and of the indiservers ``indi`` (``HOST:PORT``).

    Raises:
        NightcrewError: A server cannot be reached or read, or none offers a device nightcrew drives.
    """
    urls = list(alpaca)
    found: list[FoundDevice] = []
    if urls or alpaca_discovery:
        found.extend(await find_alpaca_devices(urls, address=address, port=port))
    for server in indi:
        host, indi_port = parse_host_port(server, 7624, "--indi")
        found.extend(await find_indi_devices(host, indi_port))
    if not found:
        raise NightcrewError("no devices found on the servers named")
    return found
