"""``nightcrew systemd DIR [--out UNITDIR] [--per-module]``: systemd units for the modules of DIR.

By default one unit, ``nightcrew.service``, runs ``nightcrew up DIR`` (the supervisor restarts
modules; ``nightcrew status`` works). With ``--per-module``, one ``nightcrew-<module>.service`` per
module file runs ``nightcrew run FILE`` and systemd restarts it. Logs go to journald with their
levels. Units are written to UNITDIR (default: the current directory); install them with
``cp *.service /etc/systemd/system/ && systemctl daemon-reload && systemctl enable --now ...``.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from nightcrew.supervisor import systemd_units

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "systemd",
        help="write systemd units for a directory of modules",
        description=__doc__.split("\n\n", 1)[1],
    )
    parser.add_argument("directory", metavar="DIR")
    parser.add_argument("--out", type=Path, default=Path("."), help="where to write the units")
    parser.add_argument(
        "--per-module", action="store_true", help="one unit per module instead of a supervisor"
    )
    parser.add_argument("--environment-file", type=Path, help="EnvironmentFile= of the units (passwords)")
    parser.set_defaults(func=_systemd)
    return parser


def _systemd(args: argparse.Namespace) -> int:
    units = systemd_units(
        Path(args.directory), per_module=args.per_module, environment_file=args.environment_file
    )
    args.out.mkdir(parents=True, exist_ok=True)
    for name, text in units.items():
        (args.out / name).write_text(text)
        print(args.out / name)
    return 0
