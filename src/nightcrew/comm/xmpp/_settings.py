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

    @property
    def bare_jid(self) -> str:
        return f"{self.local}@{self.domain}"

    @property
    def full_jid(self) -> str:
        return f"{self.bare_jid}/{self.resource}"
