"""``nightcrew up DIR``: run every module configuration in DIR as its own supervised process.

Each module file (``nightcrew check DIR`` lists them; files that are not modules, and those in a
folder ``options/``, are skipped) runs as ``nightcrew run FILE`` in a process of its own, on the
comm the file names. A module that exits or crashes is restarted after a growing delay (1 s, 2 s,
4 s … up to 60 s; a module that ran 30 s counts as healthy again); after 5 restarts within 5
minutes the supervisor gives up on it. A module whose event loop stops its heartbeat to the
supervisor for 30 s (``--frozen-after``) is ``frozen``: it is killed and restarted the same way. A
module whose configuration is broken (exit code 2) is not restarted; ``nightcrew status`` shows why.
``nightcrew status|start|stop|restart|logs`` talk to it over a Unix socket only its user can use.
SIGTERM or Ctrl-C stops every module cleanly (each closes itself), then the supervisor. With
``--comm FILE`` the supervisor joins the bus as a module (READY, or ERROR while a module is failed
or broken), so the safety watchdog can watch it.
"""

from __future__ import annotations

import argparse
import asyncio
from pathlib import Path
from typing import Any

from nightcrew.supervisor import (
    DEFAULT_FROZEN_AFTER,
    DEFAULT_STOP_TIMEOUT,
    RestartPolicy,
    Supervisor,
    default_socket_path,
)

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "up",
        help="run the modules of a directory as supervised processes",
        description=__doc__.split("\n\n", 1)[1],
    )
    parser.add_argument("directory", metavar="DIR", help="directory of module configurations")
    parser.add_argument("--socket", type=Path, help=f"control socket (default: {default_socket_path()})")
    parser.add_argument(
        "--log-dir", type=Path, default=Path("logs"), help="per-module log files (default: ./logs)"
    )
    parser.add_argument(
        "--module-log-format", choices=("text", "json"), default="text", help="format of the module log files"
    )
    parser.add_argument(
        "--max-restarts", type=int, default=5, help="restarts within 5 minutes before giving up"
    )
    parser.add_argument(
        "--comm",
        type=Path,
        metavar="FILE",
        help="join the bus with this comm (heartbeat for the safety watchdog)",
    )
    parser.add_argument(
        "--stop-timeout",
        type=float,
        default=DEFAULT_STOP_TIMEOUT,
        help=f"seconds a module may take to close (park, close the roof) before it is killed "
        f"(default {DEFAULT_STOP_TIMEOUT:g}; a frozen one is killed after --frozen-after)",
    )
    parser.add_argument(
        "--frozen-after",
        type=_frozen_after,
        default=DEFAULT_FROZEN_AFTER,
        metavar="SECONDS",
        help="seconds (1 to 86400) without a heartbeat from a module's event loop before it is killed "
        f"and restarted as frozen (default: {DEFAULT_FROZEN_AFTER:g}; 0: not watched)",
    )
    parser.set_defaults(func=_up)
    return parser


def _frozen_after(text: str) -> float:
    """0 (off), or 1 s to a day: shorter would have modules beat many times a second."""
    try:
        seconds = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number of seconds: {text!r}") from None
    if not (seconds == 0 or 1 <= seconds <= 86400):
        raise argparse.ArgumentTypeError(f"must be 0 (off) or 1 to 86400 seconds, got {text}")
    return seconds


def _up(args: argparse.Namespace) -> int:
    supervisor = Supervisor(
        Path(args.directory),
        socket_path=args.socket or default_socket_path(),
        log_dir=args.log_dir,
        log_format=args.module_log_format,
        policy=lambda: RestartPolicy(max_restarts=args.max_restarts),
        stop_timeout=args.stop_timeout,
        comm_file=args.comm,
        frozen_after=args.frozen_after or None,
    )
    asyncio.run(supervisor.run())
    return 0
