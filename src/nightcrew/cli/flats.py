"""``nightcrew flats fit DIR``: fit new exposure-time functions from a night's twilight flats.

Reads every FITS file under DIR with IMAGETYP ``skyflat``, groups them by filter and binning and
fits ``exp(a*(h + b))`` to the exposure times that would have reached the target level (see
:mod:`nightcrew.flatfield.fit`). The solar altitude comes from the ``SUNALT`` card the flat-fielder
writes, else from DATE-OBS and the site cards (SITELAT, SITELONG); target and bias levels from
``FLATTGT``/``FLATBIAS`` unless given. Saturated or nearly empty frames are left out. Prints the
functions as a ``functions:`` block for the FlatField configuration and plots exposure time against
solar altitude (points and fit, one colour per filter/binning) to a PNG when matplotlib is installed
(``pip install 'nightcrew[plot]'``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.images.flat_frames import Group, read_flats

__all__ = ["add_parser", "read_flats", "run_fit"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "flats", help="twilight flat fields: fit exposure-time functions", description="Twilight flat fields."
    )
    commands = parser.add_subparsers(dest="flats_command", metavar="COMMAND", required=True)
    fit = commands.add_parser(
        "fit",
        help="fit exposure-time functions of the solar altitude from a night's flats",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    fit.add_argument("directory", metavar="DIR", type=Path, help="directory with the night's flats")
    fit.add_argument("--target", type=float, help="target level in ADU (default: FLATTGT card, else 30000)")
    fit.add_argument("--bias", type=float, help="bias level in ADU (default: FLATBIAS card, else 0)")
    fit.add_argument("--plot", type=Path, metavar="PNG", help="plot file (default: DIR/flat-exptime-fit.png)")
    fit.add_argument("--no-plot", action="store_true", help="print the functions only")
    fit.set_defaults(func=run_fit)
    return parser


def run_fit(args: argparse.Namespace) -> int:
    from nightcrew.flatfield.fit import ExposureFit, fit_exposure_function

    if not args.directory.is_dir():
        raise ConfigError(f"DIR {args.directory} is not a directory")
    groups, levels, skipped = read_flats(args.directory, args.target, args.bias)
    for note in skipped:
        print(f"skipped {note}", file=sys.stderr)
    if not groups:
        raise NightcrewError(f"no usable sky flats under {args.directory}")
    fits: dict[Group, ExposureFit] = {}
    for group, samples in sorted(groups.items()):
        target, bias = levels[group]
        try:
            fits[group] = fit_exposure_function(samples, target, bias)
        except ValueError as exc:
            print(f"{group[0]} {group[1]}: no fit: {exc}", file=sys.stderr)
    if not fits:
        raise NightcrewError("no filter/binning had enough flats to fit")
    for (filter_name, binning), fit in fits.items():
        print(
            f"# {filter_name} {binning}: {len(fit.altitudes)} flats ({fit.rejected} clipped), "
            f"h {fit.altitudes.min():.2f}..{fit.altitudes.max():.2f} deg, rms {100 * fit.rms:.2f} %"
        )
    print("functions:")
    for filter_name in sorted({f for f, _ in fits}):
        entries = ", ".join(f'"{b}": "{fit.expression}"' for (f, b), fit in fits.items() if f == filter_name)
        print(f"  {filter_name}: {{{entries}}}")
    if not args.no_plot:
        path = args.plot or args.directory / "flat-exptime-fit.png"
        if plot_fits(fits, path):
            print(f"plot: {path}", file=sys.stderr)
        else:
            print("no plot: matplotlib is not installed (pip install 'nightcrew[plot]')", file=sys.stderr)
    return 0


def plot_fits(fits: dict[Group, Any], path: Path) -> bool:
    """Exposure time vs solar altitude, points and fitted curves, log scale; False without matplotlib."""
    try:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure
        from matplotlib.ticker import FormatStrFormatter
    except ImportError:
        return False
    import numpy as np

    figure = Figure(figsize=(7.0, 4.5), dpi=100)
    FigureCanvasAgg(figure)  # attaches itself: no pyplot, no global state
    axes = figure.add_subplot()
    for index, ((filter_name, binning), fit) in enumerate(fits.items()):
        colour = f"C{index % 10}"
        axes.scatter(fit.altitudes, fit.times, s=14, color=colour, label=f"{filter_name} {binning}")
        h = np.linspace(fit.altitudes.min() - 0.3, fit.altitudes.max() + 0.3, 100)
        axes.plot(h, fit(h), color=colour, linewidth=1.2, label=fit.expression)
    axes.set_yscale("log")
    for axis_format in (axes.yaxis.set_major_formatter, axes.yaxis.set_minor_formatter):
        axis_format(FormatStrFormatter("%g"))
    axes.set_xlabel("solar altitude h [deg]")
    axes.set_ylabel("exposure time for the target level [s]")
    axes.invert_xaxis()  # the evening's course: the Sun sinks from left to right
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize="small")
    axes.set_title("Twilight flats: exposure time vs solar altitude")
    figure.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path)
    return True
