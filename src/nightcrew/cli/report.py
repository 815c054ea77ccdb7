"""``nightcrew report OUT_DIR``: write the night report of a ``nightcrew sim`` output directory.

Reads the night's records (``events.jsonl``) and frames (``frames/*.fits``) and writes
``report.html`` beside them, with thumbnails in ``thumbnails/``: summary numbers, a timeline of
tasks against weather, roof and Sun, where the good-weather dark time went (and each task's time to
its first science frame), the tasks, the scheduler's plans, focus curves, the sky flats'
exposure-time fit, guiding RMS and every frame, and the progress of each cadence request in the
night's task archive (``tasks.sqlite``). ``nightcrew sim`` does this at the end of a night.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from nightcrew.errors import ConfigError

__all__ = ["add_parser"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "report",
        help="write the night report (report.html) of a nightcrew sim output directory",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    parser.add_argument("out_dir", metavar="OUT_DIR", type=Path, help="the output directory of nightcrew sim")
    parser.set_defaults(func=_report_command)
    return parser


def _report_command(args: argparse.Namespace) -> int:
    from nightcrew.night.cadences import stored_cadences
    from nightcrew.night.engine import TASKS_FILE
    from nightcrew.report import write_report

    if not (args.out_dir / "events.jsonl").is_file():
        raise ConfigError(
            f"{args.out_dir} holds no night (no events.jsonl): run nightcrew sim --out {args.out_dir}"
        )
    print(write_report(args.out_dir, cadences=stored_cadences(args.out_dir / TASKS_FILE)))
    return 0
