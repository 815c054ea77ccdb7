"""Alpaca devices for ``nightcrew init`` and ``nightcrew alpaca discover --write``: what exists, by role.

The servers' management API (or, without one, a probe of device numbers) says which devices exist;
a dome is asked whether it turns (``CanSetAzimuth``: a dome, else a roll-off roof) and a filter wheel
for its filter names, so the files written need no editing for either.
"""

from __future__ import annotations

import logging
from collections.abc import Awaitable, Iterable
from typing import Any

from nightcrew.bridges.alpaca.client import AlpacaClient
from nightcrew.bridges.alpaca.discovery import (
    DISCOVERY_PORT,
    ConfiguredDevice,
    ServerInfo,
    describe_server,
    discover_servers,
)
from nightcrew.errors import NightcrewError
from nightcrew.night.init._found import FoundDevice

__all__ = ["ALPACA_ROLES", "find_alpaca_devices", "found_on_server"]

log = logging.getLogger(__name__)

#: Alpaca DeviceType (lower case) → role and the nightcrew module class driving it. A dome that
#: cannot turn is a roof (AlpacaRoof) instead.
ALPACA_ROLES: dict[str, tuple[str, str]] = {
    "telescope": ("telescope", "nightcrew.modules.alpaca.AlpacaTelescope"),
    "camera": ("camera", "nightcrew.modules.alpaca.AlpacaCamera"),
    "dome": ("dome", "nightcrew.modules.alpaca.AlpacaDome"),
    "focuser": ("focuser", "nightcrew.modules.alpaca.AlpacaFocuser"),
    "filterwheel": ("filters", "nightcrew.modules.alpaca.AlpacaFilterWheel"),
    "rotator": ("rotator", "nightcrew.modules.alpaca.AlpacaRotator"),
    "safetymonitor": ("safetymonitor", "nightcrew.modules.alpaca.AlpacaSafetyMonitor"),
    "observingconditions": ("conditions", "nightcrew.modules.alpaca.AlpacaObservingConditions"),
    "switch": ("switch", "nightcrew.modules.alpaca.AlpacaSwitch"),
    "covercalibrator": ("cover", "nightcrew.modules.alpaca.AlpacaCoverCalibrator"),
}
_ROOF_CLASS = "nightcrew.modules.alpaca.AlpacaRoof"


async def find_alpaca_devices(
    servers: Iterable[str], *, address: str = "255.255.255.255", port: int = DISCOVERY_PORT, wait: float = 1.0
) -> list[FoundDevice]:
    """The devices of the given servers (``http://host:port``), or of those answering UDP discovery.

    Raises:
        NightcrewError: No server answered, or one cannot be read (the message names it).
    """
    urls = list(servers)
    if not urls:
        urls = [server.url for server in await discover_servers(address, port=port, wait=wait)]
        if not urls:
            raise NightcrewError(f"no Alpaca server answered the discovery query at {address}:{port}")
    found: list[FoundDevice] = []
    for url in urls:
        try:
            info = await describe_server(url)
        except (NightcrewError, ValueError) as exc:
            raise NightcrewError(f"Alpaca server {url}: {exc}") from None
        found.extend(await found_on_server(info))
    return found


async def found_on_server(server: ServerInfo) -> list[FoundDevice]:
    """The devices of one described server that nightcrew drives (others are logged and left out)."""
    found = []
    async with AlpacaClient(server.url, timeout=5.0) as client:
        for device in server.devices:
            kind = ALPACA_ROLES.get(device.device_type.lower())
            if kind is None:
                log.warning("%s %s at %s: no nightcrew module", device.device_type, device.number, server.url)
                continue
            found.append(await _found(client, server, device, *kind))
    return found


async def _found(
    client: AlpacaClient, server: ServerInfo, device: ConfiguredDevice, role: str, cls: str
) -> FoundDevice:
    alpaca = client.device(device.device_type.lower(), device.number)
    filters: tuple[str, ...] = ()
    if role == "dome" and not await _ask(alpaca.get("cansetazimuth"), False):
        role, cls = "roof", _ROOF_CLASS
    if role == "filters":
        names = await _ask(alpaca.get("names"), [])
        filters = tuple(str(n) for n in names) if isinstance(names, list) else ()
    where = f"{server.name or server.url}" + (f" (UniqueID {device.unique_id})" if device.unique_id else "")
    return FoundDevice(
        role=role,
        config={"class": cls, "server": server.url, "device_number": device.number},
        description=f"Alpaca {device.device_type} {device.number} '{device.name}' on {where}",
        filter_names=filters,
    )


async def _ask(call: Awaitable[Any], default: Any) -> Any:
    """A device property, or ``default`` when the device will not tell (not connected, not implemented)."""
    try:
        return await call
    except NightcrewError as exc:
        log.info("using %r: %s", default, exc)
        return default
