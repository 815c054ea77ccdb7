"""``nightcrew audit FILE``: show the audit trail of state-changing calls, filtered.

One line per call: time, caller, ``module.method(arguments)`` and the outcome (``ok``,
``forbidden`` or the error class). ``--caller``, ``--module``, ``--method`` (a pattern such as
``open_*``) and ``--outcome`` narrow it down; ``--json`` prints the records as stored.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import asdict
from typing import Any

from nightcrew.security import read_audit

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "audit", help="show the audit trail of state-changing calls", description=__doc__.split("\n\n", 1)[1]
    )
    parser.add_argument("file", metavar="FILE", help="the audit file (a comm's 'audit:' key)")
    parser.add_argument("--caller", help="only calls by this account")
    parser.add_argument("--module", help="only calls to this module")
    parser.add_argument("--method", help="only methods matching this pattern")
    parser.add_argument("--outcome", help="only this outcome (ok, forbidden, an error class)")
    parser.add_argument("--json", action="store_true", help="print the stored JSON records")
    parser.set_defaults(func=_run)
    return parser


def _run(args: argparse.Namespace) -> int:
    try:
        records = list(
            read_audit(
                args.file, caller=args.caller, module=args.module, method=args.method, outcome=args.outcome
            )
        )
    except OSError as exc:
        print(f"nightcrew: error: {args.file}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    for record in records:
        if args.json:
            print(json.dumps(asdict(record), ensure_ascii=False))
        else:
            print(
                f"{record.time}  {record.caller}  {record.module}.{record.method}"
                f"({', '.join(record.arguments)})  {record.outcome}"
            )
    return 0
