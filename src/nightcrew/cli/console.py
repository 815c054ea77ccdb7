"""``nightcrew console --comm FILE.yaml [--config CONSOLE.yaml]``: the observatory in a browser.

Runs the web console (:class:`~nightcrew.modules.console.WebConsole`) as a module on the comm
described in ``--comm`` (the operator's account, as for ``nightcrew shell``) until Ctrl-C. Its
options (accounts, port, ``show_*``, widgets, site, vfs) come from ``--config``; without accounts
there, a one-time account ``operator`` is made with the password in $NIGHTCREW_CONSOLE_PASSWORD or
a random one, printed on start. ``--hash-password`` reads a password and prints the hash to put in
the accounts.
"""

from __future__ import annotations

import argparse
import asyncio
import getpass
import signal
import sys
from typing import Any

from nightcrew.cli._operator import add_comm_argument, load_comm
from nightcrew.config import build_object, load_config
from nightcrew.errors import ConfigError
from nightcrew.modules.console import WebConsole, hash_password
from nightcrew.night.console import AnnouncedConsole, one_time_accounts

__all__ = ["add_parser"]

_CLASS = f"{WebConsole.__module__}.{WebConsole.__name__}"


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "console", help="serve the web console", description=__doc__.split("\n\n", 1)[1]
    )
    add_comm_argument(parser)
    parser.add_argument(
        "--config", metavar="CONSOLE.yaml", help="the console's options (accounts, port, ...)"
    )
    parser.add_argument("--host", default=None, help="address to listen on (default 127.0.0.1)")
    parser.add_argument("--port", type=int, default=None, help="port to listen on (default 37180)")
    parser.add_argument("--hash-password", action="store_true", help="read a password, print its hash, exit")
    parser.set_defaults(func=_command)
    return parser


def _command(args: argparse.Namespace) -> int:
    if args.hash_password:
        print(hash_password(_read_password()))
        return 0
    config: Any = load_config(args.config) if args.config else {}
    if config.get("class", _CLASS) not in (_CLASS, "nightcrew.modules.console.WebConsole"):
        raise ConfigError(f"the console's class is {_CLASS}", file=args.config, key="class")
    config["class"] = f"{__name__}.{AnnouncedConsole.__name__}"
    for key, value in (("host", args.host), ("port", args.port)):
        if value is not None:
            config[key] = value
    if not config.get("accounts"):
        config["accounts"], config["password"] = one_time_accounts()
    config["comm"] = load_comm(args.comm)
    console = build_object(config, WebConsole)
    assert isinstance(console, WebConsole)
    asyncio.run(_serve(console))
    return 0


def _read_password() -> str:
    if sys.stdin.isatty():
        password = getpass.getpass("password: ")
        if getpass.getpass("again: ") != password:
            raise ConfigError("the two passwords differ")
    else:
        password = sys.stdin.readline().rstrip("\n")
    if not password:
        raise ConfigError("an empty password")
    return password


async def _serve(console: WebConsole) -> None:
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, stop.set)
    try:
        await console.open()
        await stop.wait()
    finally:
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.remove_signal_handler(sig)
        await console.close()
