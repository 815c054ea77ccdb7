"""``nightcrew sim``: run the simulated observatory through a whole robotic night, fast.

All modules of the bundled observatory (``examples/observatory``: weather station, roof, telescope,
focuser, filter wheel, camera, and in ``robotic/`` the weather verdict, scheduler, mastermind,
focus series, flat fields, acquisition, guiding, seeing, the camera's cooling and a recorder) run
in this process on one virtual clock (it jumps ahead whenever everything waits, so the same
options and ``--seed`` give the same night on any machine under any load; ``--speed`` runs an
accelerated clock instead), from dusk to dawn of ``--date``: the scheduler plans the bundled sample tasks,
the mastermind runs them (sky flats, bias and darks, focus, science), the weather (``--weather``)
may interrupt them, and at the end the telescope parks and the roof closes (also after an error or
Ctrl-C). Frames, the event record (events.jsonl), the task archive and the night report
(report.html) go to ``--out``. ``--quick`` runs the same engine on a short task list (biases and
darks, a few fields) for an hour after dusk. ``--indi PORT`` also serves the devices to INDI
clients (KStars/Ekos, Stellarium) on 127.0.0.1:PORT and ``--console [PORT]`` the web console while
the night runs (on an accelerated clock unless ``--speed`` says otherwise: 320x, ``--quick`` 60x).
``--archive`` reduces every object frame while the night runs (the Pipeline module, into
``--out/reduced``, with masters it builds in ``--out/masters``) and at the night's end copies every
raw frame, master and reduced frame into an image archive in ``--out/archive``, to browse with
``nightcrew archive --config OUT/archive/archive.yaml``.
Progress is shown on stderr, a summary on stdout.
"""

from __future__ import annotations

import argparse
from dataclasses import fields
from datetime import date
from datetime import time as time_of_day
from pathlib import Path
from typing import Any

from nightcrew.night.options import DEFAULT_NIGHT, SimOptions
from nightcrew.night.plan import WEATHER_SCENARIOS

__all__ = ["DEFAULT_NIGHT", "add_parser", "sim_options"]

_OPTION_NAMES = [field.name for field in fields(SimOptions)]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "sim", help="run the simulated observatory through a night", description=__doc__.split("\n\n", 1)[1]
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("sim-output"),
        help="output directory: frames, events.jsonl, tasks.sqlite, report.html",
    )
    parser.add_argument("--date", type=_night, default=DEFAULT_NIGHT, help="night (YYYY-MM-DD)")
    parser.add_argument(
        "--speed",
        type=_positive,
        default=None,
        help="run an accelerated clock at this many clock seconds per wall second instead of the "
        "virtual clock (not repeatable: a busy machine changes the night)",
    )
    parser.add_argument("--seed", type=int, default=None, help="replace the seeds of all modules")
    parser.add_argument(
        "--weather",
        choices=WEATHER_SCENARIOS,
        default=None,
        help="clear (--quick's default); interruption: an hour of rain mid-night (the default); "
        "random: from --seed",
    )
    parser.add_argument(
        "--start",
        type=_clock_time,
        default=None,
        help="UTC time (HH:MM) to start at instead of dusk; before noon: the morning after --date",
    )
    parser.add_argument(
        "--hours",
        type=_positive,
        default=None,
        help="stop after this many clock hours (default: at dawn; --quick: 1)",
    )
    season = parser.add_argument_group("a season of nights (--nights)")
    season.add_argument(
        "--nights",
        type=_count,
        default=1,
        help="run this many consecutive nights from --date (each in --out/night-YYYY-MM-DD) and write "
        "a season report (season.md, season.json); try --weather random",
    )
    season.add_argument(
        "--frames",
        action="store_true",
        help="with --nights > 1: keep every night's frames (default: drop them)",
    )
    parser.add_argument(
        "--quick", action="store_true", help="a short task list after dusk instead of the sample tasks"
    )
    quick = parser.add_argument_group("the short night (--quick)")
    quick.add_argument("--targets", type=_count, default=3, help="number of star fields")
    quick.add_argument("--filters", default="V,R", help="comma-separated filters, one exposure each")
    quick.add_argument("--exposure-time", type=_positive, default=30.0, help="seconds per exposure")
    quick.add_argument(
        "--calibration-frames",
        type=_non_negative,
        default=3,
        help="biases and darks taken before the roof opens, so the night can be reduced (0: none)",
    )
    parser.add_argument(
        "--configs", type=Path, default=None, help="directory of module files (default: the bundled ones)"
    )
    parser.add_argument(
        "--indi",
        type=_port,
        default=None,
        metavar="PORT",
        help="also serve the telescope, camera, focuser, filter wheel and roof to INDI clients "
        "(KStars/Ekos, Stellarium) on 127.0.0.1:PORT (INDI's usual port is 7624)",
    )
    parser.add_argument(
        "--console",
        type=_port,
        nargs="?",
        const=37180,
        default=None,
        metavar="PORT",
        help="serve the web console on 127.0.0.1:PORT (default 37180; 0: a free one) to watch the night live",
    )
    parser.add_argument(
        "--archive",
        action="store_true",
        help="reduce every object frame during the night (the Pipeline module: masters into --out/masters, "
        "reduced frames into --out/reduced) and at its end copy every raw frame, master and reduced "
        "frame into an image archive in --out/archive "
        "(browse it with nightcrew archive --config OUT/archive/archive.yaml); see docs/archive.md",
    )
    parser.add_argument("-v", "--verbose", action="store_true", help="show the modules' log messages")
    alpaca = parser.add_argument_group("serving the devices to Alpaca clients (--alpaca)")
    alpaca.add_argument(
        "--alpaca",
        type=_port,
        default=None,
        metavar="PORT",
        help="instead of a night, serve the devices as ASCOM Alpaca devices on 127.0.0.1:PORT in real "
        "time (--speed to change) until Ctrl-C; see docs/alpaca.md",
    )
    alpaca.add_argument(
        "--alpaca-discovery-port", type=_port, default=32227, help="Alpaca discovery UDP port (%(default)s)"
    )
    parser.set_defaults(func=_sim_command)
    return parser


def _sim_command(args: argparse.Namespace) -> int:
    from nightcrew.night.run import run_sim  # the engine's imports only when it runs

    return run_sim(sim_options(args))


def sim_options(args: argparse.Namespace) -> SimOptions:
    """The parsed arguments as the options :func:`~nightcrew.night.options.run_sim` takes."""
    values = {name: getattr(args, name) for name in _OPTION_NAMES if name != "show_logs"}
    return SimOptions(**values, show_logs=bool(args.verbose or getattr(args, "debug", False)))


def _night(text: str) -> date:
    try:
        return date.fromisoformat(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a date (YYYY-MM-DD): {text!r}") from None


def _clock_time(text: str) -> time_of_day:
    try:
        return time_of_day.fromisoformat(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a time (HH:MM): {text!r}") from None


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def _count(text: str, minimum: int = 1) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if value < minimum:
        raise argparse.ArgumentTypeError(f"must be >= {minimum}, got {text}")
    return value


def _port(text: str) -> int:
    port = _count(text, minimum=0)  # 0: a free one (the console prints which)
    if port > 65535:
        raise argparse.ArgumentTypeError(f"not a port number (0..65535): {text}")
    return port


def _non_negative(text: str) -> int:
    return _count(text, minimum=0)
