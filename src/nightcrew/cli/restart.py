"""``nightcrew restart [MODULE]``: stop and start a module (or all) (via the supervisor)."""

from __future__ import annotations

import argparse
from typing import Any

from nightcrew.cli._supervisor_client import add_control_parser

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    return add_control_parser(subparsers, "restart", "stop and start a module (or all)")
