"""``nightcrew check PATH ...``: validate configuration files without starting anything.

Every file is loaded, validated and built exactly as ``run`` builds it (constructor checks
included; nothing is opened or connected), so the two agree on every file. Prints ``OK FILE`` for
every valid file and one ``FILE:LINE: key 'x': message`` line (on stderr)
for every invalid one; exits 0 when all are valid, else 2. A directory stands for every
``*.yaml``/``*.yml`` below it (recursively), except files that other files there include: those
fragments are checked as part of the files that include them.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Any

from nightcrew.cli.run import build_file
from nightcrew.config import config_files
from nightcrew.errors import ConfigError

__all__ = ["add_parser", "check_file", "run_check"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "check",
        help="validate configuration files",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    parser.add_argument("paths", nargs="+", metavar="PATH", help="a YAML file, or a directory of them")
    parser.set_defaults(func=run_check)
    return parser


def check_file(path: Path) -> None:
    """Load, validate and build (without opening) what one file describes, exactly as ``run`` does.

    Building runs the constructors' own checks (ranges, combinations of keys), so a file ``check``
    calls OK is one ``run`` accepts. Raises :class:`ConfigError` for the first problem.
    """
    build_file(path, expected=None)


def run_check(args: argparse.Namespace) -> int:
    files = config_files(args.paths)
    if not files:
        print(f"nightcrew: error: no *.yaml files in {' '.join(args.paths)}", file=sys.stderr)
        return 2
    all_valid = True
    for path in files:
        try:
            check_file(path)
        except ConfigError as exc:
            if getattr(args, "debug", False):
                raise
            all_valid = False
            # The problem may lie in an included file; then say which checked file it belongs to.
            if not exc.file:
                print(f"{path}: {exc}", file=sys.stderr)
            elif os.path.normpath(exc.file) != os.path.normpath(path):
                print(f"{exc} (included from {path})", file=sys.stderr)
            else:
                print(exc, file=sys.stderr)
        else:
            print(f"OK {path}")
    from nightcrew.images.astrometry import observatory_coverage_problems  # astropy: only here

    for problem in observatory_coverage_problems(files):  # a camera field the index files cannot solve
        print(f"nightcrew: error: {problem}", file=sys.stderr)
        all_valid = False
    return 0 if all_valid else 2
