"""The answers ``nightcrew init`` needs, checked when they are made (one clear error per bad answer)."""

from __future__ import annotations

import zoneinfo
from dataclasses import dataclass
from typing import Literal

from nightcrew.errors import ConfigError
from nightcrew.site import Site

__all__ = ["CommKind", "InitOptions", "parse_host_port"]

CommKind = Literal["embedded", "xmpp"]


@dataclass(frozen=True)
class InitOptions:
    """What the observatory directory says beside its devices.

    Args:
        latitude, longitude, elevation, site_name: Where it stands (degrees north/east, metres).
        timezone: The local time zone (IANA name), for people reading times; nightcrew works in UTC.
        horizon: Lowest altitude the telescope may point at, degrees.
        comm: ``embedded`` (every module in one process on this machine, ``nightcrew run``) or
            ``xmpp`` (one process per module on an XMPP server, ``nightcrew up``).
        xmpp_server, domain, room: Where the modules meet (``host:port``, JID domain, room name).
        ca_file: The server's certificate, relative to the directory (``nightcrew server init
            xmpp`` run in the directory writes it there).
        images: Where the camera writes its frames, relative to the directory.
        console_port: The web console's port on 127.0.0.1.
        good_weather_after: Seconds the weather must stay good before the roof may open.
    """

    latitude: float
    longitude: float
    elevation: float = 0.0
    site_name: str = ""
    timezone: str = "UTC"
    horizon: float = 15.0
    comm: CommKind = "xmpp"
    xmpp_server: str = "127.0.0.1:5222"
    domain: str = "observatory.local"
    room: str = "nightcrew"
    ca_file: str = ""
    images: str = "images"
    console_port: int = 37180
    good_weather_after: float = 900.0

    def __post_init__(self) -> None:
        try:
            Site(self.latitude, self.longitude, self.elevation, self.site_name)
        except ValueError as exc:
            raise ConfigError(str(exc), key="site") from None
        if not -180.0 <= self.longitude <= 180.0:
            raise ConfigError(f"must be within -180..180 degrees, got {self.longitude}", key="longitude")
        try:
            zoneinfo.ZoneInfo(self.timezone)
        except (ValueError, zoneinfo.ZoneInfoNotFoundError):
            raise ConfigError(
                f"unknown time zone {self.timezone!r} (e.g. Europe/Berlin)", key="timezone"
            ) from None
        if not 0.0 <= self.horizon < 90.0:
            raise ConfigError(f"must be within 0..90 degrees, got {self.horizon}", key="horizon")
        if self.comm not in ("embedded", "xmpp"):
            raise ConfigError(f"must be 'embedded' or 'xmpp', got {self.comm!r}", key="comm")
        parse_host_port(self.xmpp_server, 5222, "xmpp_server")
        if not self.domain or "@" in self.domain or "/" in self.domain:
            raise ConfigError(f"not an XMPP domain: {self.domain!r}", key="domain")
        if not 0 < self.console_port < 65536:
            raise ConfigError(
                f"must be a TCP port within 1..65535, got {self.console_port}", key="console_port"
            )

        if not self.good_weather_after >= 0:
            raise ConfigError(
                f"must be >= 0 seconds, got {self.good_weather_after}", key="good_weather_after"
            )

    @property
    def certificate(self) -> str:
        return self.ca_file or f"xmpp/certs/{self.domain}.crt"


def parse_host_port(text: str, default_port: int, key: str) -> tuple[str, int]:
    """``host:port`` (or ``host`` alone) → (host, port); ConfigError naming ``key`` when malformed."""
    host, _, port_text = text.rpartition(":") if ":" in text else (text, "", str(default_port))
    try:
        port = int(port_text)
    except ValueError:
        port = 0
    if not host or not 0 < port < 65536:
        raise ConfigError(f"expected HOST:PORT, got {text!r}", key=key)
    return host, port
