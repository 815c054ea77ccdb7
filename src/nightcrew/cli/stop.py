"""``nightcrew stop [MODULE]``: stop a module (or all); it is not restarted (via the supervisor)."""

from __future__ import annotations

import argparse
from typing import Any

from nightcrew.cli._supervisor_client import add_control_parser

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    return add_control_parser(subparsers, "stop", "stop a module (or all); it is not restarted")
