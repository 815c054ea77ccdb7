"""Connection settings of an XmppComm, checked when the comm is built (no I/O)."""

from __future__ import annotations

import ipaddress
import re
from dataclasses import dataclass, field

from nightcrew.errors import ConfigError

__all__ = ["DEFAULT_PORT", "DEFAULT_RESOURCE", "XmppSettings", "is_loopback", "parse_jid", "parse_server"]

DEFAULT_PORT = 5222
#: Resource of a module's session; a second process with the same account takes over the session.
DEFAULT_RESOURCE = "nightcrew"
_SERVER = re.compile(r"\[(?P<v6>[^\]]+)\](?::(?P<p6>\d+))?|(?P<host>[^:\[\]]+)(?::(?P<port>\d+))?")
_JID = re.compile(r"(?P<local>[^@/\s]+)@(?P<domain>[^@/\s]+)(?:/(?P<resource>\S+))?")


def parse_jid(jid: str) -> tuple[str, str, str | None]:
    """``local@domain[/resource]`` → (local, domain, resource); ConfigError if malformed."""
    match = _JID.fullmatch(jid.strip())
    if match is None:
        raise ConfigError(f"'{jid}' is not a JID like camera@observatory.local", key="jid")
    return match["local"], match["domain"].lower(), match["resource"]


def parse_server(server: str | None, domain: str) -> tuple[str, int]:
    """``host[:port]`` (IPv6 in brackets) → (host, port); defaults: the JID's domain, 5222."""
    if not server:
        return domain, DEFAULT_PORT
    match = _SERVER.fullmatch(server)
    if match is None:
        raise ConfigError(f"'{server}' is not host:port", key="server")
    host = match["v6"] or match["host"]
    port = int(match["p6"] or match["port"] or DEFAULT_PORT)
    if not 0 < port < 65536:
        raise ConfigError(f"port {port} out of range", key="server")
    return host, port


def is_loopback(host: str) -> bool:
    """Whether ``host`` names this machine (where TLS is optional)."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


@dataclass(frozen=True)
class XmppSettings:
    """Everything needed to connect; built from the ``comm:`` keys."""

    local: str
    domain: str
    resource: str
    password: str = field(repr=False)  # never in a log line or a traceback's locals
    host: str
    port: int
    room_jid: str
    require_tls: bool
    verify_tls: bool
    ca_file: str | None
    connect_timeout: float
    #: Wall seconds between pings to the server (None: no pings) and how long one may go unanswered.
    ping_interval: float | None = 10.0
    ping_timeout: float = 10.0

    @classmethod
    def from_options(
        cls,
        jid: str,
        password: str,
        *,
        resource: str,
        room: str | None,
        server: str | None = None,
        require_tls: bool | None = None,
        verify_tls: bool = True,
        ca_file: str | None = None,
        connect_timeout: float = 10.0,
        ping_interval: float | None = 10.0,
        ping_timeout: float = 10.0,
    ) -> XmppSettings:
        """Settings from a config's keys, each checked (ConfigError naming the key).

        ``resource`` is used when the JID names none; ``room`` is a room JID or a name in the
        domain's ``conference.`` service (None: no room).
        """
        local, domain, own_resource = parse_jid(jid)
        host, port = parse_server(server, domain)
        if not password:
            raise ConfigError(f"{local}@{domain} needs a password", key="password")
        if require_tls is False and not is_loopback(host):
            raise ConfigError(f"TLS cannot be turned off off loopback ({host})", key="require_tls")
        if ping_interval is not None and not ping_interval > 0:
            raise ConfigError(f"must be > 0 seconds or null, got {ping_interval}", key="ping_interval")
        if not ping_timeout > 0:
            raise ConfigError(f"must be > 0 seconds, got {ping_timeout}", key="ping_timeout")
        return cls(
            local=local,
            domain=domain,
            resource=own_resource or resource,
            password=password,
            host=host,
            port=port,
            room_jid="" if room is None else (room if "@" in room else f"{room}@conference.{domain}").lower(),
            require_tls=not is_loopback(host) if require_tls is None else require_tls,
            verify_tls=verify_tls,
            ca_file=ca_file,
            connect_timeout=connect_timeout,
            ping_interval=None if ping_interval is None else float(ping_interval),
            ping_timeout=float(ping_timeout),
        )

    @property
    def bare_jid(self) -> str:
        return f"{self.local}@{self.domain}"

    @property
    def full_jid(self) -> str:
        return f"{self.bare_jid}/{self.resource}"
