"""``nightcrew reduce RAW_DIR OUT_DIR``: reduce a night of raw FITS frames.

RAW_DIR is a directory of FITS files, or a ``nightcrew sim`` output (its ``frames`` directory is
used).

Builds master bias/dark/flat frames from the calibration frames (grouped by IMAGETYP, binning,
filter and exposure time), calibrates every science frame, detects its stars, plate-solves it (the
catalog matcher first, then the solve service given with --solver, then astrometry.net's
solve-field; the matcher and solve-field with the index files of --index-dir, e.g. the simulated
sky's that ``nightcrew sim`` prints) and writes it with its source catalog to OUT_DIR, plus
``OUT_DIR/summary.ecsv`` with one row per raw file. Progress goes to stderr. Running it again skips
finished work; a broken file is reported and skipped.
"""

from __future__ import annotations

import argparse
import asyncio
import sys
from collections import Counter
from pathlib import Path
from typing import Any

from nightcrew.errors import ConfigError

__all__ = ["add_parser", "run_reduce"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "reduce",
        help="reduce a night of raw frames",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    parser.add_argument("raw_dir", metavar="RAW_DIR", type=Path, help="directory of raw FITS files")
    parser.add_argument("out_dir", metavar="OUT_DIR", type=Path, help="directory for the results")
    parser.add_argument(
        "--pixel-scale",
        type=float,
        default=None,
        metavar="ARCSEC",
        help="unbinned pixel scale (default: headers)",
    )
    parser.add_argument(
        "--index-dir",
        type=Path,
        default=None,
        metavar="DIR",
        help="astrometry.net index files for the matcher and solve-field (default: /usr/share/astrometry)",
    )
    parser.add_argument(
        "--solver", default=None, metavar="URL", help="plate-solving service (nightcrew solver) to try"
    )
    parser.add_argument("--no-solve-field", action="store_true", help="do not fall back to solve-field")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    parser.set_defaults(func=run_reduce)
    return parser


def run_reduce(args: argparse.Namespace) -> int:
    # Imported here: astropy and the image stack load in ~1 s, which other commands should not pay.
    from nightcrew.images.reduce import SUMMARY_NAME, ReduceOptions, find_raw_frames, reduce_night

    if not args.raw_dir.is_dir():
        raise ConfigError(f"RAW_DIR {args.raw_dir} is not a directory")
    if args.pixel_scale is not None and args.pixel_scale <= 0:
        raise ConfigError(f"--pixel-scale must be positive, got {args.pixel_scale}")
    if args.solver is not None and not args.solver.startswith(("http://", "https://")):
        raise ConfigError(f"--solver must be an http:// or https:// URL, got {args.solver!r}")
    if args.index_dir is not None and not any(args.index_dir.expanduser().glob("index-*.fits")):
        raise ConfigError(f"--index-dir {args.index_dir}: no astrometry.net index files (index-*.fits) there")
    find_raw_frames(args.raw_dir)  # no frames: say where it looked before creating OUT_DIR
    options = ReduceOptions(
        pixel_scale_arcsec=args.pixel_scale,
        index_dir=None if args.index_dir is None else str(args.index_dir.expanduser()),
        solver_url=args.solver,
        solve_field=not args.no_solve_field,
    )
    rows = asyncio.run(
        reduce_night(args.raw_dir, args.out_dir, options=options, progress=None if args.quiet else sys.stderr)
    )
    counts = Counter(row.status for row in rows)
    solved = sum(1 for row in rows if row.status == "reduced" and row.solver)
    print(
        f"{len(rows)} files: {counts['reduced']} reduced ({solved} plate-solved), "
        f"{counts['calibration']} calibration, {counts['failed']} failed, {counts['broken']} broken, "
        f"{counts['ignored']} ignored; summary in {args.out_dir / SUMMARY_NAME}"
    )
    for row in rows:
        if row.status in ("failed", "broken") or row.message:
            print(f"  {row.file}: {row.status}: {row.message}")
    return 1 if counts["failed"] else 0
