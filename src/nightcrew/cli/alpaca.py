"""``nightcrew alpaca discover``: find Alpaca servers and their devices, optionally write module files.

Sends the Alpaca discovery query to ``--address`` (the local network's broadcast address by
default; ``127.255.255.255`` for this machine only, or one server's address) and lists every
server that answers with the devices its management API reports. ``--server URL`` skips the UDP
query and asks that server directly. With ``--write DIR`` it writes one module file per device
(``telescope0.yaml``, ``camera0.yaml``, ...: class, ``server`` and ``device_number``), ready for
``nightcrew run``; existing files are never overwritten.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
from pathlib import Path
from typing import Any

import yaml

from nightcrew.bridges.alpaca.discovery import (
    DISCOVERY_PORT,
    ConfiguredDevice,
    ServerInfo,
    describe_server,
    discover_servers,
)
from nightcrew.errors import ConfigError, NightcrewError

__all__ = ["MODULE_CLASSES", "add_parser", "module_config"]

#: Alpaca DeviceType (as the management API spells it) → the nightcrew module class driving it.
MODULE_CLASSES = {
    "telescope": "nightcrew.modules.alpaca.AlpacaTelescope",
    "camera": "nightcrew.modules.alpaca.AlpacaCamera",
    "dome": "nightcrew.modules.alpaca.AlpacaDome",
    "focuser": "nightcrew.modules.alpaca.AlpacaFocuser",
    "filterwheel": "nightcrew.modules.alpaca.AlpacaFilterWheel",
    "rotator": "nightcrew.modules.alpaca.AlpacaRotator",
    "safetymonitor": "nightcrew.modules.alpaca.AlpacaSafetyMonitor",
    "observingconditions": "nightcrew.modules.alpaca.AlpacaObservingConditions",
    "switch": "nightcrew.modules.alpaca.AlpacaSwitch",
    "covercalibrator": "nightcrew.modules.alpaca.AlpacaCoverCalibrator",
}


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "alpaca", help="ASCOM Alpaca tools", description="ASCOM Alpaca tools."
    )
    commands = parser.add_subparsers(dest="alpaca_command", metavar="COMMAND", required=True)
    discover = commands.add_parser(
        "discover",
        help="find Alpaca servers and devices; write module files",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    discover.add_argument(
        "--address",
        default="255.255.255.255",
        help="where to send the discovery query: a broadcast address or one host (default: %(default)s)",
    )
    discover.add_argument("--port", type=int, default=DISCOVERY_PORT, help="discovery UDP port (%(default)s)")
    discover.add_argument(
        "--wait", type=float, default=1.0, help="seconds to wait for answers per query (%(default)s)"
    )
    discover.add_argument(
        "--server",
        action="append",
        default=[],
        metavar="URL",
        help="ask this server (http://host:port) directly",
    )
    discover.add_argument(
        "--write", type=Path, metavar="DIR", help="write one module file per device into DIR"
    )
    discover.set_defaults(func=_discover_command)
    return parser


def module_config(server: ServerInfo, device: ConfiguredDevice) -> dict[str, Any] | None:
    """The module configuration driving ``device``, or None for a device type nightcrew lacks."""
    cls = MODULE_CLASSES.get(device.device_type.lower())
    if cls is None:
        return None
    return {"class": cls, "server": server.url, "device_number": device.number}


def _discover_command(args: argparse.Namespace) -> int:
    if not args.wait > 0:
        raise ConfigError(f"--wait must be > 0 seconds, got {args.wait}")
    servers = asyncio.run(_find(args))
    if not servers:
        where = ", ".join(args.server) or f"{args.address}:{args.port}"
        print(f"no Alpaca server answered ({where})", file=sys.stderr)
        return 1
    for server in servers:
        print(_describe(server))
    if args.write is not None:
        for path in _write_configs(servers, args.write):
            print(f"wrote {path}")
    return 0


async def _find(args: argparse.Namespace) -> list[ServerInfo]:
    urls = list(args.server)
    if not urls:
        found = await discover_servers(args.address, port=args.port, wait=args.wait)
        urls = [server.url for server in found]
    servers = []
    for url in urls:
        try:
            servers.append(await describe_server(url))
        except (NightcrewError, ValueError) as exc:
            print(f"{url}: {exc}", file=sys.stderr)
    return servers


def _describe(server: ServerInfo) -> str:
    title = f"{server.url}  {server.name or '(no name)'}"
    if server.manufacturer or server.version:
        title += f"  ({' '.join(p for p in (server.manufacturer, server.version) if p)})"
    if server.location:
        title += f"  at {server.location}"
    lines = [title]
    for device in server.devices:
        lines.append(f"  {device.device_type} {device.number}: {device.name}  [{device.unique_id}]")
    if not server.devices:
        lines.append("  (no devices)")
    return "\n".join(lines)


def _write_configs(servers: list[ServerInfo], directory: Path) -> list[Path]:
    """Write every device's file; refuse before writing anything if one exists already."""
    planned: dict[Path, tuple[ServerInfo, ConfiguredDevice, dict[str, Any]]] = {}
    for server in servers:
        for device in server.devices:
            config = module_config(server, device)
            if config is None:
                print(f"skipped {device.device_type} {device.number} at {server.url}: no nightcrew module")
                continue
            stem = f"{device.device_type.lower()}{device.number}"
            path = directory / f"{stem}.yaml"
            if path in planned:  # a second server with the same kind of device
                path = directory / f"{stem}-{server.url.rsplit(':', 1)[-1]}.yaml"
            planned[path] = (server, device, config)
    existing = [str(path) for path in planned if path.exists()]
    if existing:
        raise ConfigError(f"not overwriting existing files: {', '.join(existing)}")
    directory.mkdir(parents=True, exist_ok=True)
    for path, (server, device, config) in planned.items():
        header = (
            f"# {device.device_type} {device.number} '{device.name}' on the Alpaca server "
            f"{server.name or server.url} (UniqueID {device.unique_id}),\n"
            "# written by `nightcrew alpaca discover`. Add the options of the module's base here.\n"
        )
        if device.device_type.lower() == "telescope":
            header += "# A telescope needs the site: site: {latitude: ..., longitude: ..., elevation: ...}\n"
        path.write_text(header + yaml.safe_dump(config, sort_keys=False), encoding="utf-8")
    return list(planned)
