"""``nightcrew alpaca discover``: find Alpaca servers and their devices, optionally write module files.

Sends the Alpaca discovery query to ``--address`` (the local network's broadcast address by
default; ``127.255.255.255`` for this machine only, or one server's address) and lists every
server that answers with the devices its management API reports. ``--server URL`` skips the UDP
query and asks that server directly. With ``--write DIR`` it writes one module file per device
that exists, named by role as ``nightcrew init`` names them (``telescope.yaml``, ``camera.yaml``,
``roof.yaml`` or ``dome.yaml``, ``filters.yaml``, ...; ``camera1.yaml``, ``camera2.yaml`` where a
role has several): class, ``server`` and ``device_number``, ready for ``nightcrew run``. Existing
files are never overwritten; ``nightcrew init`` writes a whole observatory directory instead.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
from pathlib import Path
from typing import Any

from nightcrew.bridges.alpaca.discovery import (
    DISCOVERY_PORT,
    ServerInfo,
    describe_server,
    discover_servers,
)
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.night.init import FoundDevice, found_on_server, module_text, name_by_role

__all__ = ["add_parser"]


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
    simulator = commands.add_parser(
        "simulator",
        help="set up alpaca-simulators with an offline star table (to try nightcrew without hardware)",
        description=(
            "Write DIR/config.yaml for alpaca-simulators (PyPI) and the offline star table its camera "
            "reads (DIR/gaia_sources.db, from nightcrew's bundled catalogue: Gaia stars to G = 10), so "
            "its camera shows real stars without the internet. Then run: alpaca-simulators --host "
            "127.0.0.1 --port 11111 --config DIR/config.yaml"
        ),
    )
    simulator.add_argument("directory", type=Path, metavar="DIR")
    simulator.add_argument("--latitude", type=float, default=48.0, help="the mount's site (%(default)s)")
    simulator.add_argument("--longitude", type=float, default=8.0, help="the mount's site (%(default)s)")
    simulator.add_argument("--elevation", type=float, default=1000.0, help="metres (%(default)s)")
    simulator.set_defaults(func=_simulator_command)
    return parser


def _simulator_command(args: argparse.Namespace) -> int:
    from nightcrew.testing.alpaca import TEST_OVERRIDES, merge_config, write_simulator_config

    site = {"sitelatitude": args.latitude, "sitelongitude": args.longitude, "siteelevation": args.elevation}
    overrides = merge_config(TEST_OVERRIDES, {"devices": {"telescope": {0: site}}})
    path = write_simulator_config(args.directory, overrides=overrides)
    print(f"wrote {path} and {args.directory / 'gaia_sources.db'}")
    print(f"run: alpaca-simulators --host 127.0.0.1 --port 11111 --config {path}")
    return 0


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
        for path in asyncio.run(_write_configs(servers, args.write)):
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


async def _write_configs(servers: list[ServerInfo], directory: Path) -> list[Path]:
    """Write every device's file; refuse before writing anything if one exists already."""
    found = []
    for server in servers:
        found.extend(await found_on_server(server))
    return await asyncio.to_thread(_write_files, name_by_role(found), directory)


def _write_files(devices: dict[str, FoundDevice], directory: Path) -> list[Path]:
    planned = {directory / f"{name}.yaml": device for name, device in devices.items()}
    existing = [str(path) for path in planned if path.exists()]
    if existing:
        raise ConfigError(f"not overwriting existing files: {', '.join(existing)}")
    directory.mkdir(parents=True, exist_ok=True)
    for path, device in planned.items():
        header = (
            f"{device.description},\nwritten by `nightcrew alpaca discover`. "
            "Add the options of the module's base here."
        )
        if device.role == "telescope":
            header += "\nA telescope needs the site: site: {latitude: ..., longitude: ..., elevation: ...}"
        path.write_text(module_text(header, device.config), encoding="utf-8")
    return list(planned)
