"""A private Prosody: configuration, accounts and the server process, all inside one directory.

Layout of the directory: ``prosody.cfg.lua``, ``server.json`` (what ``init`` was told),
``certs/<domain>.crt|key``, ``data/`` (accounts), ``prosody.pid``, ``prosody.log``.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

from nightcrew.comm.xmpp import is_loopback
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.server._accounts import Account
from nightcrew.server._tls import make_self_signed

__all__ = [
    "ServerSettings",
    "init_server",
    "prosody_config",
    "register_account",
    "server_status",
    "start_server",
    "stop_server",
]

_START_TIMEOUT = 10.0
_STOP_TIMEOUT = 10.0


@dataclass(frozen=True)
class ServerSettings:
    """Where the server listens, which domains it serves, and who may use the room.

    ``room_owners``: bare JIDs made owners of every room (component admins); with them only they may
    create rooms, and a module can ban an account that squats its name. ``members_only``: only
    owners and members may enter a room. ``require_tls``: TLS for every client connection, also on
    loopback (None: required off loopback only).
    """

    host: str
    port: int
    domains: list[str]
    room_owners: list[str] = field(default_factory=list)
    members_only: bool = False
    require_tls: bool | None = None

    @classmethod
    def load(cls, directory: Path) -> ServerSettings:
        path = directory / "server.json"
        if not path.is_file():
            raise ConfigError(f"{directory} holds no server (run 'nightcrew server init {directory}' first)")
        data = json.loads(path.read_text())
        return cls(
            host=data["host"],
            port=int(data["port"]),
            domains=list(data["domains"]),
            room_owners=list(data.get("room_owners", [])),
            members_only=bool(data.get("members_only", False)),
            require_tls=data.get("require_tls"),
        )

    def save(self, directory: Path) -> None:
        (directory / "server.json").write_text(json.dumps(asdict(self), indent=2) + "\n")


def _lua(value: str) -> str:
    return json.dumps(value)  # a JSON string literal is a valid Lua string literal


def prosody_config(directory: Path, settings: ServerSettings) -> str:
    """The text of ``prosody.cfg.lua``."""
    d = directory.resolve()
    tls = not is_loopback(settings.host) if settings.require_tls is None else settings.require_tls
    require_tls = "true" if tls else "false"
    lines = [
        "-- Written by `nightcrew server init`; see docs/xmpp-servers.md. Edit freely, init overwrites it.",
        "run_as_root = true  -- CI and containers run as root; the data lives in this directory only",
        f"pidfile = {_lua(str(d / 'prosody.pid'))}",
        f"data_path = {_lua(str(d / 'data'))}",
        f"interfaces = {{ {_lua(settings.host)} }}",
        f"c2s_ports = {{ {settings.port} }}",
        "c2s_direct_tls_ports = {}",
        "-- Only what the nightcrew protocol needs; no s2s (a private server), no rate limits (mod_limits",
        "-- is not loaded) and no offline storage (events and calls are not for later).",
        "-- groups: a shared roster (see groups_file below), which pyobs-core peers need (docs/pyobs.md).",
        'modules_enabled = { "roster"; "saslauth"; "tls"; "disco"; "ping"; "posix"; "groups" }',
        'modules_disabled = { "s2s"; "offline" }',
        'authentication = "internal_hashed"  -- SCRAM-SHA-1 (passwords are stored hashed)',
        f"c2s_require_encryption = {require_tls}",
        "allow_registration = false",
        "-- Modules refuse stanzas over 1 MiB themselves (docs/protocol.md); larger ones end the",
        "-- sender's stream here, before the server spends seconds parsing them.",
        "c2s_stanza_size_limit = 2 * 1024 * 1024",
        "-- Calls are many small stanzas answered at once: send them without waiting (no Nagle).",
        "network_settings = { nagle = false; opportunistic_writes = true }",
        f'log = {{ {{ levels = {{ min = "info" }}, to = "file", filename = {_lua(str(d / "prosody.log"))} }} }}',  # noqa: E501
        f"certificates = {_lua(str(d / 'certs'))}",
        "",
    ]
    for domain in settings.domains:
        cert, key = d / "certs" / f"{domain}.crt", d / "certs" / f"{domain}.key"
        ssl = f"ssl = {{ certificate = {_lua(str(cert))}; key = {_lua(str(key))} }}"
        lines += [
            f"VirtualHost {_lua(domain)}",
            f"    {ssl}",
            "    -- Every account is a contact of every other: pyobs-core finds its peers by presence.",
            f"    groups_file = {_lua(str(groups_file(d, domain)))}",
            "",
            "-- PubSub, where pyobs-core modules publish their events (one node per sender and event).",
            "-- Prosody lets only its admins make nodes: every account is one here (and nowhere else).",
            f'Component {_lua("pubsub." + domain)} "pubsub"',
            f"    {ssl}",
            f"    admins = {{ {'; '.join(_lua(jid) for jid in _members(d, domain))} }}",
            "    autocreate_on_publish = true",
            "",
            "-- The room all modules meet in: non-anonymous (real JIDs visible), created on first join.",
            f'Component {_lua("conference." + domain)} "muc"',
            f"    {ssl}",
            "    muc_room_locking = false",
            "    muc_room_default_public_jids = true",
            "    muc_room_default_history_length = 0",
            "    muc_tombstones = false",
            *_room_access(settings),
            "",
        ]
    return "\n".join(lines)


def _room_access(settings: ServerSettings) -> list[str]:
    """The MUC options that keep the room to the observatory's accounts (see docs/security.md)."""
    if not settings.room_owners:
        return []
    owners = "; ".join(_lua(jid) for jid in settings.room_owners)
    lines = [
        "    -- The observatory's accounts own every room (component_admins_as_room_owners, the",
        "    -- default): only they create rooms, and a module can ban an account holding its name.",
        f"    admins = {{ {owners} }}",
        "    restrict_room_creation = true",
    ]
    if settings.members_only:
        lines += [
            "    muc_room_default_members_only = true  -- nobody else enters (XEP-0045 §7.2.6)",
            "    -- Rooms outlive their occupants, so module names reserved in them stay reserved.",
            "    muc_room_default_persistent = true",
        ]
    return lines


def init_server(
    directory: str | os.PathLike[str],
    accounts: list[Account],
    *,
    host: str,
    port: int,
    domains: list[str],
    room_owners: list[str] | None = None,
    members_only: bool = False,
    require_tls: bool | None = None,
) -> ServerSettings:
    """Write config and certificates into ``directory`` and register ``accounts``.

    ``room_owners``, ``members_only``, ``require_tls``: see :class:`ServerSettings`.
    """
    _require("prosody")
    root = Path(directory)
    if server_status(root) is not None:
        raise NightcrewError(f"the server in {root} is running; stop it before init")
    all_domains = sorted({*domains, *(a.domain for a in accounts)})
    if not all_domains:
        raise ConfigError("no domain: give module configs with comm.jid or --domain")
    if members_only and not room_owners:
        raise ConfigError("a members-only room needs owners (the observatory's accounts)")
    settings = ServerSettings(
        host=host,
        port=port,
        domains=all_domains,
        room_owners=sorted(jid.lower() for jid in room_owners or []),
        members_only=members_only,
        require_tls=require_tls,
    )
    (root / "data").mkdir(parents=True, exist_ok=True)
    for domain in all_domains:
        make_self_signed(root / "certs", domain)
        roster = groups_file(root, domain)
        if not roster.exists():  # init again keeps the accounts registered before
            roster.write_text("[+observatory]\n")  # '+': every account sees the group
    (root / "prosody.cfg.lua").write_text(prosody_config(root, settings))
    settings.save(root)
    for account in accounts:
        register_account(root, account)
    return settings


def groups_file(directory: Path, domain: str) -> Path:
    """The shared roster of ``domain``: the accounts every account has as contacts (mod_groups)."""
    return directory / f"groups-{domain}.txt"


def _members(directory: Path, domain: str) -> list[str]:
    path = groups_file(directory, domain)
    return [line for line in path.read_text().split() if "@" in line] if path.exists() else []


def register_account(directory: str | os.PathLike[str], account: Account) -> None:
    """Create ``account`` (or set its password); works while the server runs, too."""
    root = Path(directory)
    result = subprocess.run(
        ["prosodyctl", "--config", str(root / "prosody.cfg.lua"), "register", account.user, account.domain],
        input=f"{account.password}\n{account.password}\n",
        capture_output=True,
        text=True,
        check=False,
    )
    if result.returncode != 0:
        raise NightcrewError(f"registering {account.jid} failed: {_last_line(result.stdout + result.stderr)}")
    roster = groups_file(root, account.domain)
    if roster.exists() and account.jid not in _members(root, account.domain):
        # Shared roster and PubSub admins are read by Prosody when it starts.
        with roster.open("a") as out:
            out.write(f"{account.jid}\n")
        (root / "prosody.cfg.lua").write_text(prosody_config(root, ServerSettings.load(root)))


def start_server(directory: str | os.PathLike[str]) -> int:
    """Start Prosody in the background and wait until it accepts connections; returns its pid."""
    _require("prosody")
    root = Path(directory).resolve()
    settings = ServerSettings.load(root)
    running = server_status(root)
    if running is not None:
        return running
    # Prosody daemonizes itself (-D): it outlives this process and is found again by its pidfile.
    with open(root / "prosody.out", "ab") as out:
        result = subprocess.run(
            ["prosody", "-D", "--config", str(root / "prosody.cfg.lua")],
            stdin=subprocess.DEVNULL,
            stdout=out,
            stderr=subprocess.STDOUT,
            check=False,
            timeout=_START_TIMEOUT,
        )
    if result.returncode != 0:
        raise NightcrewError(f"prosody did not start: {_log_tail(root)}")
    deadline = time.monotonic() + _START_TIMEOUT
    while time.monotonic() < deadline:
        pid = server_status(root)
        if pid is not None and _accepts(settings.host, settings.port):
            return pid
        time.sleep(0.05)
    raise NightcrewError(f"prosody did not listen on {settings.host}:{settings.port}: {_log_tail(root)}")


def stop_server(directory: str | os.PathLike[str]) -> bool:
    """Stop the server started in ``directory``; False if it was not running."""
    root = Path(directory)
    pid = server_status(root)
    if pid is None:
        return False
    os.kill(pid, signal.SIGTERM)
    deadline = time.monotonic() + _STOP_TIMEOUT
    while time.monotonic() < deadline and _alive(pid):
        time.sleep(0.05)
    if _alive(pid):
        os.kill(pid, signal.SIGKILL)
    (root / "prosody.pid").unlink(missing_ok=True)
    return True


def server_status(directory: str | os.PathLike[str]) -> int | None:
    """The pid of the server running from ``directory``, or None."""
    pidfile = Path(directory) / "prosody.pid"
    try:
        pid = int(pidfile.read_text().strip())
    except (OSError, ValueError):
        return None
    return pid if _alive(pid) else None


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    stat = Path(f"/proc/{pid}/stat")
    return not (stat.is_file() and stat.read_text().split(") ", 1)[-1].startswith("Z"))


def _accepts(host: str, port: int) -> bool:
    try:
        with socket.create_connection((host, port), timeout=0.2):
            return True
    except OSError:
        return False


def _require(command: str) -> None:
    if shutil.which(command) is None:
        raise NightcrewError(f"'{command}' is not installed (Debian: apt-get install prosody)")


def _last_line(text: str) -> str:
    lines = [line for line in text.strip().splitlines() if line.strip() and "*" not in line]
    return lines[-1] if lines else "no output"


def _log_tail(root: Path) -> str:
    for name in ("prosody.log", "prosody.out"):
        path = root / name
        if path.is_file():
            lines = [line for line in path.read_text().splitlines() if "error" in line.lower()]
            if lines:
                return lines[-1]
    return "see prosody.log"
