"""What ``nightcrew status|start|stop|restart|logs`` share: the socket option, the request, the table."""

from __future__ import annotations

import argparse
import asyncio
import time
from pathlib import Path
from typing import Any

from nightcrew.supervisor import default_socket_path, send_request

__all__ = ["add_control_parser"]


def add_control_parser(subparsers: Any, command: str, text: str) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(command, help=text, description=text)
    parser.add_argument("module", nargs="?", help="one module (default: all)")
    parser.add_argument(
        "--socket", type=Path, help=f"the supervisor's control socket (default: {default_socket_path()})"
    )
    parser.set_defaults(func=_run, command=command)
    return parser


def _run(args: argparse.Namespace) -> int:
    request: dict[str, Any] = {"command": args.command, "module": args.module}
    if args.command == "logs":
        request["lines"] = args.lines
    reply = asyncio.run(send_request(args.socket or default_socket_path(), request))
    if args.command == "logs":
        print("\n".join(reply["lines"]))
        return 0
    modules = reply["modules"]
    print(format_table(modules))
    if args.command == "status":
        return 0 if all(m["state"] == "running" for m in modules) else 3
    return 0


def format_table(modules: list[dict[str, Any]]) -> str:
    """One line per module: name, state, pid, restarts, for how long, and what went wrong."""
    now = time.time()
    width = max((len(m["name"]) for m in modules), default=6)
    lines = [f"{'MODULE':<{width}}  {'STATE':<8}  {'PID':>7}  {'RESTARTS':>8}  {'SINCE':>7}  LAST PROBLEM"]
    for m in modules:
        pid = str(m["pid"]) if m["pid"] else "-"
        problem = m["error"] or m["last_exit"] or ""
        lines.append(
            f"{m['name']:<{width}}  {m['state']:<8}  {pid:>7}  {m['restarts']:>8}  "
            f"{_age(now - m['since']):>7}  {problem}"
        )
    return "\n".join(lines)


def _age(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f}s"
    if seconds < 7200:
        return f"{seconds / 60:.0f}m"
    return f"{seconds / 3600:.0f}h"
