"""Alpaca discovery (UDP) and the management API: finding servers and the devices they offer.

Facts from the ASCOM Alpaca API specification: a client sends the datagram ``alpacadiscovery1``
to UDP port 32227 (as a broadcast, or to one host); every Alpaca server listening there answers
the sender with the JSON ``{"AlpacaPort": <HTTP port>}``. The client then reads
``/management/v1/description`` and ``/management/v1/configureddevices`` of each server.

* :class:`DiscoveryResponder` is the server side, used by the AlpacaServer module. It listens on
  one address (loopback by default). On a loopback address it also listens on the loopback
  broadcast address (127.255.255.255), since Linux hands broadcasts only to sockets bound to the
  broadcast or the wildcard address; it always answers from the unicast socket, so the client
  sees the server's real address.
* :func:`discover_servers` sends the query to ``address`` (a broadcast address, or one host) and
  collects answers; :func:`describe_server` reads a server's management API with the one Alpaca
  client (:class:`~nightcrew.bridges.alpaca.client.AlpacaClient`).
"""

from __future__ import annotations

import asyncio
import ipaddress
import json
import logging
import socket
from dataclasses import dataclass
from typing import Any

from nightcrew.bridges.alpaca.client import DEVICE_TYPES, AlpacaClient, _json_reply
from nightcrew.bridges.alpaca.errors import AlpacaConnectionError, AlpacaReplyError
from nightcrew.errors import NightcrewError, RemoteTimeoutError

__all__ = [
    "DISCOVERY_PORT",
    "DISCOVERY_QUERY",
    "ConfiguredDevice",
    "DiscoveredServer",
    "DiscoveryResponder",
    "ServerInfo",
    "describe_server",
    "discover_servers",
]

log = logging.getLogger(__name__)

DISCOVERY_PORT = 32227
DISCOVERY_QUERY = b"alpacadiscovery1"
_LOOPBACK_BROADCAST = "127.255.255.255"
#: URL device type → DeviceType as the management API spells it.
_TYPE_NAMES = {
    "camera": "Camera",
    "covercalibrator": "CoverCalibrator",
    "dome": "Dome",
    "filterwheel": "FilterWheel",
    "focuser": "Focuser",
    "observingconditions": "ObservingConditions",
    "rotator": "Rotator",
    "safetymonitor": "SafetyMonitor",
    "switch": "Switch",
    "telescope": "Telescope",
}


class DiscoveryResponder:
    """Answers Alpaca discovery queries with the HTTP port of the server.

    Args:
        alpaca_port: The HTTP port to announce.
        host: Address to listen on (``127.0.0.1``: this machine only; ``0.0.0.0``: the network).
        port: UDP port; 0 picks a free one (see :attr:`port` after :meth:`open`).
    """

    def __init__(self, alpaca_port: int, *, host: str = "127.0.0.1", port: int = DISCOVERY_PORT) -> None:
        self._alpaca_port = alpaca_port
        self._host = host
        self._requested_port = port
        self._transports: list[asyncio.DatagramTransport] = []
        self._port = 0

    @property
    def port(self) -> int:
        """The UDP port listened on (after :meth:`open`)."""
        return self._port

    async def open(self) -> None:
        if self._transports:
            return
        loop = asyncio.get_running_loop()
        unicast = _udp_socket(self._host, self._requested_port, reuse=False)
        self._port = unicast.getsockname()[1]
        reply_to, _ = await loop.create_datagram_endpoint(lambda: _Responder(self), sock=unicast)
        self._transports.append(reply_to)
        if _is_loopback(self._host):
            try:
                broadcast = _udp_socket(_LOOPBACK_BROADCAST, self._port, reuse=True)
            except OSError as exc:  # answering unicast queries still works
                log.warning("discovery: cannot listen on %s:%d: %s", _LOOPBACK_BROADCAST, self._port, exc)
            else:
                listener, _ = await loop.create_datagram_endpoint(lambda: _Responder(self), sock=broadcast)
                self._transports.append(listener)

    async def close(self) -> None:
        transports, self._transports = self._transports, []
        for transport in transports:
            transport.close()

    def answer(self, data: bytes, sender: tuple[str, int]) -> None:
        """Answer one datagram (from any of the sockets) through the unicast socket."""
        if not data.strip().lower().startswith(b"alpacadiscovery"):
            return  # not for us (the spec allows later versions, alpacadiscovery2, ...)
        if self._transports:
            payload = json.dumps({"AlpacaPort": self._alpaca_port}).encode()
            self._transports[0].sendto(payload, sender)


class _Responder(asyncio.DatagramProtocol):
    def __init__(self, responder: DiscoveryResponder) -> None:
        self._responder = responder

    def datagram_received(self, data: bytes, addr: tuple[str | Any, int]) -> None:
        self._responder.answer(data, (str(addr[0]), int(addr[1])))


def _is_loopback(host: str) -> bool:
    try:
        return ipaddress.ip_address(host).is_loopback and ipaddress.ip_address(host).version == 4
    except ValueError:
        return host == "localhost"


def _udp_socket(host: str, port: int, *, reuse: bool) -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        if reuse:  # several servers on one machine may all hear the broadcasts
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind(("127.0.0.1" if host == "localhost" else host, port))
    except OSError:
        sock.close()
        raise
    sock.setblocking(False)
    return sock


# --- the client side -------------------------------------------------------------------------------


@dataclass(frozen=True)
class DiscoveredServer:
    """An Alpaca server that answered a discovery query."""

    host: str
    port: int

    @property
    def url(self) -> str:
        return f"http://{self.host}:{self.port}"


class _Collector(asyncio.DatagramProtocol):
    def __init__(self) -> None:
        self.found: list[DiscoveredServer] = []

    def datagram_received(self, data: bytes, addr: tuple[str | Any, int]) -> None:
        try:
            port = json.loads(data)["AlpacaPort"]
            if not isinstance(port, int) or isinstance(port, bool) or not 0 < port < 65536:
                raise ValueError(f"AlpacaPort {port!r} is not a port number")
        except (ValueError, KeyError, TypeError) as exc:
            log.warning("discovery: ignored a malformed answer from %s: %r (%s)", addr[0], data[:80], exc)
            return
        server = DiscoveredServer(str(addr[0]), port)
        if server not in self.found:
            self.found.append(server)


async def discover_servers(
    address: str = "255.255.255.255", *, port: int = DISCOVERY_PORT, wait: float = 1.0, queries: int = 2
) -> list[DiscoveredServer]:
    """The servers answering a discovery query sent to ``address`` within ``wait`` seconds.

    Args:
        address: Broadcast address (``255.255.255.255``: the local network; ``127.255.255.255``:
            this machine) or the address of one server.
        port: The UDP port servers listen on.
        wait: Wall seconds to wait for answers after each query.
        queries: How many queries to send (UDP may lose one).
    """
    if not wait > 0 or queries < 1:
        raise ValueError(f"need wait > 0 and queries >= 1, got {wait} and {queries}")
    loop = asyncio.get_running_loop()
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_BROADCAST, 1)
    sock.bind(("127.0.0.1", 0) if _is_loopback(address) or address == _LOOPBACK_BROADCAST else ("", 0))
    sock.setblocking(False)
    collector = _Collector()
    transport, _ = await loop.create_datagram_endpoint(lambda: collector, sock=sock)
    try:
        for _ in range(queries):
            transport.sendto(DISCOVERY_QUERY, (address, port))
            # Answers arrive whenever servers send them; the window is what discovery is.
            await asyncio.sleep(wait)
    finally:
        transport.close()
    return list(collector.found)


# --- the management API --------------------------------------------------------------------------


@dataclass(frozen=True)
class ConfiguredDevice:
    """One entry of ``/management/v1/configureddevices``."""

    name: str
    device_type: str
    number: int
    unique_id: str


@dataclass(frozen=True)
class ServerInfo:
    """What a server says about itself and its devices."""

    url: str
    name: str
    manufacturer: str
    version: str
    location: str
    devices: tuple[ConfiguredDevice, ...]


async def describe_server(url: str, *, http_timeout: float = 5.0, probe: bool = True) -> ServerInfo:
    """Read the management API of the server at ``url`` (``http://host:port``).

    A server without the management API (HTTP 404 there, e.g. alpaca-simulators) is asked for
    the ``name`` of device 0, 1, ... of every type instead, when ``probe`` is true.

    Raises:
        AlpacaConnectionError: The server cannot be reached.
        AlpacaReplyError: Its answers are not valid management replies.
    """
    async with AlpacaClient(url, timeout=http_timeout) as client:
        base = client.server.rstrip("/")
        where = f"{base}/management/v1"
        try:
            description = await _management_value(client, base, "description")
        except AlpacaReplyError as exc:
            if not (probe and "HTTP 404" in str(exc)):
                raise
            return ServerInfo(base, "", "", "", "", await _probe_devices(client))
        devices = await _management_value(client, base, "configureddevices")
    if not isinstance(description, dict):
        raise AlpacaReplyError(f"{where}/description: Value is not an object: {description!r}")
    if not isinstance(devices, list):
        raise AlpacaReplyError(f"{where}/configureddevices: Value is not a list: {devices!r}")
    return ServerInfo(
        url=base,
        name=str(description.get("ServerName", "")),
        manufacturer=str(description.get("Manufacturer", "")),
        version=str(description.get("ManufacturerVersion", "")),
        location=str(description.get("Location", "")),
        devices=tuple(_device(entry, f"{where}/configureddevices") for entry in devices),
    )


#: Device numbers probed per type on a server without the management API.
_PROBED_NUMBERS = 8


async def _probe_devices(client: AlpacaClient) -> tuple[ConfiguredDevice, ...]:
    """The devices that exist: device 0, 1, ... of each type, until one does not.

    A device exists when it answers ``GET connected`` (every device type has it, connected or
    not). A server may answer for numbers it has no device for with an error reply instead of
    HTTP 404 (alpaca-simulators: "Device camera:1 not found"); that, too, ends the type.
    """
    found = []
    for device_type in sorted(DEVICE_TYPES):
        for number in range(_PROBED_NUMBERS):
            device = client.device(device_type, number)
            try:
                await device.get("connected")
            except (AlpacaConnectionError, RemoteTimeoutError):
                raise  # the server, not the device, is the problem
            except NightcrewError:
                break  # HTTP 400/404 or an error reply: no such device
            try:
                name = await device.get("name")
            except (AlpacaConnectionError, RemoteTimeoutError):
                raise
            except NightcrewError:
                name = ""  # the device exists but will not say its name (e.g. not connected)
            found.append(ConfiguredDevice(str(name), _TYPE_NAMES[device_type], number, ""))
    return tuple(found)


async def _management_value(client: AlpacaClient, base: str, member: str) -> Any:
    from yarl import URL

    url = URL(base) / "management" / "v1" / member
    where = f"{base}/management/v1/{member}"
    _, body = await client.request("GET", url, where, {})
    reply = _json_reply(body, where)
    if "Value" not in reply:
        raise AlpacaReplyError(f"{where}: the reply has no Value")
    return reply["Value"]


def _device(entry: Any, where: str) -> ConfiguredDevice:
    try:
        number = entry["DeviceNumber"]
        if not isinstance(number, int) or isinstance(number, bool) or number < 0:
            raise ValueError(f"DeviceNumber {number!r} is not a device number")
        return ConfiguredDevice(
            name=str(entry["DeviceName"]),
            device_type=str(entry["DeviceType"]),
            number=number,
            unique_id=str(entry["UniqueID"]),
        )
    except (KeyError, TypeError, ValueError) as exc:
        raise AlpacaReplyError(f"{where}: malformed device entry {entry!r}: {exc}") from None
