"""``nightcrew solver``: the plate-solving service (astrometry.net with its indexes kept loaded).

Listens for ``POST /solve`` with a star list (JSON, see ``docs/pipeline.md``) and answers with
FITS WCS cards, well under a second with a position hint. Point an astrometry processor at it with
``nightcrew.images.astrometry.RemoteAstrometry`` (``solver: {class: ...RemoteSolver, url: http://HOST:PORT}``),
or ``nightcrew
reduce --solver URL``. With --field (the camera's field width in arcmin) it refuses to start when
the index files hold no quads small enough for that field, saying what to install. Prints
``listening on URL`` once ready; stops on SIGINT/SIGTERM.
"""

from __future__ import annotations

import argparse
import asyncio
import importlib.util
from pathlib import Path
from typing import Any

from nightcrew.cli._running import stop_on_signals
from nightcrew.errors import ConfigError

__all__ = ["add_parser", "run_solver"]


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "solver",
        help="run the plate-solving service",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on (default: 127.0.0.1)")
    parser.add_argument("--port", type=int, default=8091, help="TCP port (default 8091; 0: any free one)")
    parser.add_argument(
        "--index-dir",
        type=Path,
        default=None,
        metavar="DIR",
        help="astrometry.net index files (default: /usr/share/astrometry)",
    )
    parser.add_argument(
        "--field",
        type=float,
        default=None,
        metavar="ARCMIN",
        help="width of the smallest camera field to solve: refused if the index files cannot",
    )
    parser.add_argument(
        "--sip-order", type=int, default=2, help="SIP distortion order of the solution (0: pure TAN)"
    )
    parser.add_argument(
        "--time-limit", type=float, default=10.0, metavar="S", help="longest solve in seconds (default 10)"
    )
    parser.set_defaults(func=run_solver)
    return parser


def run_solver(args: argparse.Namespace) -> int:
    from nightcrew.images.astrometry import index_coverage_problem
    from nightcrew.services.solver import DEFAULT_INDEX_DIR, SolverProcess, SolverService, find_index_files

    if not 0 <= args.port <= 65535:
        raise ConfigError(f"--port must be within 0..65535, got {args.port}")
    if importlib.util.find_spec("astrometry") is None:
        raise ConfigError(
            "nightcrew solver needs the 'astrometry' package (GPL-3, an optional extra): "
            "pip install 'nightcrew[solver]'"
        )
    if args.sip_order < 0:
        raise ConfigError(f"--sip-order must be >= 0, got {args.sip_order}")
    if not args.time_limit > 0:
        raise ConfigError(f"--time-limit must be positive, got {args.time_limit}")
    if args.field is not None and not args.field > 0:
        raise ConfigError(f"--field must be positive, got {args.field}")
    directory: Path = args.index_dir or DEFAULT_INDEX_DIR
    try:
        indexes = find_index_files(directory)
    except FileNotFoundError as exc:
        raise ConfigError(str(exc)) from exc
    problem = None if args.field is None else index_coverage_problem(directory, args.field)
    if problem is not None:
        raise ConfigError(problem)
    solver = SolverProcess(indexes, time_limit_s=args.time_limit, sip_order=args.sip_order)
    service = SolverService(solver, host=args.host, port=args.port)
    asyncio.run(_serve(service))
    return 0


async def _serve(service: Any) -> None:
    async with stop_on_signals() as stop:
        try:
            await service.start()
            print(f"listening on {service.url}", flush=True)
            await stop.wait()
        finally:
            await service.close()
