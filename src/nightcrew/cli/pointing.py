"""``nightcrew pointing fit CSV --mount NAME --output FILE``: fit a pointing model to a series.

Reads the CSV a PointingSeries wrote (its solved rows: commanded and solved positions, the time
and the site), fits the TPoint-style terms (``--terms``, default the geometric eight and HHSH,
HHCH; see :mod:`nightcrew.astro.pointing`) with outlier rejection (``--clip`` times the RMS), prints each
term with its uncertainty and the RMS before and after, and writes the model for the telescope's
``pointing_model`` option (YAML; JSON for a ``.json`` name).
"""

from __future__ import annotations

import argparse
import csv
from pathlib import Path
from typing import Any

from nightcrew.errors import ConfigError

__all__ = ["add_parser", "run_fit"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "pointing", help="pointing models: fit one to a pointing series", description="Pointing models."
    )
    commands = parser.add_subparsers(dest="pointing_command", metavar="COMMAND", required=True)
    fit = commands.add_parser(
        "fit",
        help="fit a pointing model to a pointing series' CSV",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    fit.add_argument("csv", metavar="CSV", type=Path, help="the series' CSV")
    fit.add_argument("--mount", required=True, help="name of the telescope module the model is for")
    fit.add_argument("--output", required=True, type=Path, metavar="FILE", help="model file to write")
    fit.add_argument("--terms", help="comma-separated terms (default: IH,ID,CH,NP,MA,ME,TF,FO,HHSH,HHCH)")
    fit.add_argument("--clip", type=float, default=3.0, help="reject points beyond this many RMS (default 3)")
    fit.set_defaults(func=run_fit)
    return parser


def run_fit(args: argparse.Namespace) -> int:
    from nightcrew.astro.pointing import DEFAULT_TERMS, PointingModelError, fit_pointing_model
    from nightcrew.modules.pointing.series import pointing_pairs
    from nightcrew.modules.telescope.pointing_model import save_pointing_model

    terms = tuple(t.strip() for t in args.terms.split(",")) if args.terms else DEFAULT_TERMS
    try:
        with args.csv.open(newline="", encoding="utf-8") as stream:
            rows = list(csv.DictReader(stream))
    except OSError as exc:
        raise ConfigError(f"cannot read the series: {exc.strerror or exc}", file=str(args.csv)) from exc
    try:
        pairs, latitude = pointing_pairs(rows)
        model = fit_pointing_model(pairs, mount=args.mount, latitude=latitude, terms=terms, clip=args.clip)
    except PointingModelError as exc:
        raise ConfigError(str(exc), file=str(args.csv)) from exc
    statistics = model.statistics
    assert statistics is not None  # a fit has them
    print(f"pointing model of {args.mount}: {statistics.points} points, {statistics.rejected} rejected")
    print(f"{'term':<6} {'value [arcsec]':>15} {'sigma':>9}")
    for name, value in model.terms.items():
        print(f"{name:<6} {value:>15.2f} {model.sigmas[name]:>9.2f}")
    print(f'RMS before {statistics.rms_before:.2f}", after {statistics.rms_after:.2f}"')
    save_pointing_model(args.output, model)
    print(f"written to {args.output}")
    return 0
