"""``nightcrew archive --config ARCHIVE.yaml``: serve the image archive until Ctrl-C.

The archive stores uploaded FITS frames by DAY-OBS and instrument, indexes their headers in
SQLite (default) or PostgreSQL, and serves search, details, thumbnails, downloads and a web
frontend on HTTP (docs/archive.md). ``--new-token FILE`` writes a fresh upload token to FILE
(mode 600) for the config's ``token_file`` and exits; the token is never printed.
"""

from __future__ import annotations

import argparse
import asyncio
import signal
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from nightcrew.config import load_config
from nightcrew.errors import ConfigError

if TYPE_CHECKING:
    from nightcrew.services.archive import ArchiveServer

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "archive", help="serve the image archive", description=__doc__.split("\n\n", 1)[1]
    )
    parser.add_argument("--config", metavar="ARCHIVE.yaml", help="the archive's configuration")
    parser.add_argument("--host", default=None, help="address to listen on (overrides the config)")
    parser.add_argument("--port", type=int, default=None, help="port to listen on (overrides the config)")
    parser.add_argument("--new-token", metavar="FILE", help="write a new upload token to FILE and exit")
    parser.set_defaults(func=_command)
    return parser


def _command(args: argparse.Namespace) -> int:
    # Imported here: `nightcrew <other command>` should not pay for astropy and asyncpg.
    from nightcrew.services.archive import ArchiveServer, load_archive_config, write_new_token

    if args.new_token:
        try:
            write_new_token(Path(args.new_token))
        except FileExistsError:
            raise ConfigError(f"{args.new_token} exists; remove it first to replace the token") from None
        print(f"wrote a new upload token to {args.new_token} (mode 600)", file=sys.stderr)
        return 0
    if not args.config:
        raise ConfigError("name the archive's configuration with --config ARCHIVE.yaml (see docs/archive.md)")
    raw: dict[str, Any] = dict(load_config(args.config))
    for key, value in (("host", args.host), ("port", args.port)):
        if value is not None:
            raw[key] = value
    server = ArchiveServer(load_archive_config(raw, file=args.config))
    asyncio.run(_serve(server))
    return 0


async def _serve(server: ArchiveServer) -> None:
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, stop.set)
    try:
        await server.start()  # logs where it listens
        await stop.wait()
    finally:
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.remove_signal_handler(sig)
        await server.close()
