"""``nightcrew sim``: run the simulated observatory through a whole robotic night, fast.

All modules of the bundled observatory (``examples/sim``: weather station, roof, telescope,
focuser, filter wheel, camera, and in ``robotic/`` the weather verdict, scheduler, mastermind,
focus series, flat fields, acquisition, guiding, seeing and a recorder) run in this process on one
virtual clock (it jumps ahead whenever everything waits, so the same options and ``--seed``
give the same night on any machine under any load; ``--speed`` runs an accelerated clock instead),
from dusk to dawn of ``--date``: the scheduler plans the bundled sample tasks,
the mastermind runs them (sky flats, bias and darks, focus, science), the weather (``--weather``)
may interrupt them, and at the end the telescope parks and the roof closes (also after an error or
Ctrl-C). Frames, the event record (events.jsonl), the task archive and the night report
(report.html) go to ``--out``. ``--quick`` runs the short scripted night instead (a few fields, no
scheduler). Progress is shown on stderr, a summary on stdout.
"""

from __future__ import annotations

import argparse
import asyncio
import logging
import signal
import sys
import time
from datetime import date, datetime
from datetime import time as time_of_day
from pathlib import Path
from typing import Any, TextIO

from nightcrew.clock import AcceleratedClock, Clock, VirtualClock
from nightcrew.comm.local import LocalNetwork
from nightcrew.config import load_config, to_plain
from nightcrew.errors import ConfigError
from nightcrew.night.build import (
    SIM_RPC_GRACE,
    NightReport,
    ProgressCallback,
    build_observatory,
    bundled_observatory,
    run_night,
)
from nightcrew.night.fields import Step, choose_targets, night_start, plan_night
from nightcrew.night.plan import WEATHER_SCENARIOS
from nightcrew.site import Site

__all__ = ["add_parser", "describe_pace", "sim_clock", "site_of"]

#: A moonless autumn night (new moon on 2026-11-09) with Cygnus and Cassiopeia high after dusk.
DEFAULT_NIGHT = "2026-11-10"


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
    parser.add_argument("--date", type=_night, default=_night(DEFAULT_NIGHT), help="night (YYYY-MM-DD)")
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
        default="interruption",
        help="clear; interruption: an hour of rain mid-night (default); random: from --seed",
    )
    parser.add_argument(
        "--start",
        type=_clock_time,
        default=None,
        help="UTC time (HH:MM) to start at instead of dusk; before noon: the morning after --date",
    )
    parser.add_argument(
        "--hours", type=_positive, default=None, help="stop after this many clock hours (default: at dawn)"
    )
    parser.add_argument("--quick", action="store_true", help="the short scripted night (no scheduler)")
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


def whole_night_command(args: argparse.Namespace) -> int:
    from nightcrew.cli._sim_night import run_whole_night_command  # the heavier imports only here

    return run_whole_night_command(args)


def _sim_command(args: argparse.Namespace) -> int:
    if args.alpaca is not None:
        from nightcrew.cli._sim_alpaca import serve_alpaca_command

        return serve_alpaca_command(args)
    if not args.quick:
        return whole_night_command(args)
    directory: Path = args.configs or bundled_observatory()
    site = site_of(directory)
    start = night_start(args.date, site)
    try:
        targets = choose_targets(site, start.timestamp(), args.targets)
    except ValueError as exc:
        raise ConfigError(f"--date {args.date}: {exc}") from exc
    filters = [name.strip() for name in args.filters.split(",") if name.strip()]
    steps = plan_night(targets, list(filters) or [None], args.exposure_time, args.calibration_frames)

    # Module chatter would bury the progress line; -v (or --debug) shows it.
    quiet = not (args.verbose or args.debug)
    logger = logging.getLogger("nightcrew")
    old_level = logger.level
    if quiet:
        logger.setLevel(logging.WARNING)
    wall_start = time.monotonic()
    try:
        report = asyncio.run(_run(directory, args, start, steps, _progress_printer(sys.stderr)))
    finally:
        logger.setLevel(old_level)
    _print_summary(report, args, start, time.monotonic() - wall_start)
    return 0 if report.completed else 130


async def _run(
    directory: Path, args: argparse.Namespace, start: datetime, steps: list[Step], progress: ProgressCallback
) -> NightReport:
    clock = sim_clock(start, args.speed)
    network = LocalNetwork(rpc_grace=SIM_RPC_GRACE)
    modules = build_observatory(directory, clock=clock, out_dir=args.out, seed=args.seed, network=network)
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, stop.set)
    try:
        return await run_night(
            modules, steps, clock=clock, network=network, out_dir=args.out, progress=progress, stop=stop
        )
    finally:
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.remove_signal_handler(sig)


def sim_clock(start: datetime, speed: float | None) -> Clock:
    """The simulation's clock: virtual (repeatable, as fast as the machine allows), or with
    ``speed`` an accelerated one."""
    return VirtualClock(start) if speed is None else AcceleratedClock(start, speed=speed)


def site_of(directory: Path) -> Site:
    """The observatory's site: the one the telescope's file gives."""
    path = directory / "telescope.yaml"
    if not path.is_file():
        raise ConfigError(f"no telescope.yaml in {directory}: the night needs a telescope")
    site = load_config(path).get("site")
    if not isinstance(site, dict):
        raise ConfigError("the telescope needs a site (latitude, longitude, elevation)", file=str(path))
    try:
        return Site(**to_plain(site))
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"invalid site: {exc}", file=str(path), key="site") from exc


def _progress_printer(stream: TextIO) -> ProgressCallback:
    """Progress as one rewritten line on a terminal, one line per step elsewhere."""
    tty = stream.isatty()

    def show(number: int, total: int, step: Step, now: datetime) -> None:
        done = round(20 * (number - 1) / max(1, total - 1))
        line = f"[{'#' * done}{'.' * (20 - done)}] {number}/{total} {now:%H:%M:%S} UTC  {step.describe()}"
        if tty:
            stream.write("\r\033[K" + line + ("\n" if number == total else ""))
        else:
            stream.write(line + "\n")
        stream.flush()

    return show


def _print_summary(report: NightReport, args: argparse.Namespace, start: datetime, wall: float) -> None:
    state = "night complete" if report.completed else "night stopped early"
    print(
        f"{state}: {len(report.frames)} frames written to {args.out} "
        f"(night of {args.date}, clock from {start:%H:%M} UTC {describe_pace(args.speed)}; "
        f"{wall:.1f} s wall time)"
    )
    for path in report.files:
        print(f"  {path}")


def describe_pace(speed: float | None) -> str:
    return "on virtual time" if speed is None else f"at {speed:g}x"


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


def _non_negative(text: str) -> int:
    return _count(text, minimum=0)


def _port(text: str) -> int:
    value = _count(text, minimum=0)
    if value > 65535:
        raise argparse.ArgumentTypeError(f"not a port number (0..65535): {text}")
    return value
