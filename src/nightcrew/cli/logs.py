"""``nightcrew logs MODULE [-n LINES]``: the end of a supervised module's log file."""

from __future__ import annotations

import argparse
from typing import Any

from nightcrew.cli._supervisor_client import add_control_parser

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser = add_control_parser(subparsers, "logs", "show the end of a module's log file")
    parser.add_argument("-n", "--lines", type=int, default=50, help="how many lines (default: 50)")
    return parser
