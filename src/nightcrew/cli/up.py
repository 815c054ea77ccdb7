"""``nightcrew up DIR``: run every module configuration in DIR as its own supervised process.

Each module file (``nightcrew check DIR`` lists them; files that are not modules, and those in a
folder ``options/``, are skipped) runs as ``nightcrew run FILE`` in a process of its own, on the
comm the file names. A module that exits or crashes is restarted after a growing delay (1 s, 2 s,
4 s … up to 60 s; a module that ran 30 s counts as healthy again); after 5 restarts within 5
minutes the supervisor gives up on it. A module whose configuration is broken (exit code 2) is not
restarted; ``nightcrew status`` shows why.
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

from nightcrew.supervisor import RestartPolicy, Supervisor, default_socket_path

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
    parser.add_argument("--stop-timeout", type=float, default=20.0, help="seconds a module may take to close")
    parser.set_defaults(func=_up)
    return parser


def _up(args: argparse.Namespace) -> int:
    supervisor = Supervisor(
        Path(args.directory),
        socket_path=args.socket or default_socket_path(),
        log_dir=args.log_dir,
        log_format=args.module_log_format,
        policy=lambda: RestartPolicy(max_restarts=args.max_restarts),
        stop_timeout=args.stop_timeout,
        comm_file=args.comm,
    )
    asyncio.run(supervisor.run())
    return 0
