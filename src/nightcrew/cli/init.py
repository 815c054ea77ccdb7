"""``nightcrew init DIR``: write an observatory directory for your own Alpaca and INDI devices.

Finds the devices (``--alpaca URL`` asks that server, ``--alpaca-discovery`` sends the Alpaca UDP
query, ``--indi HOST:PORT`` asks an indiserver) and writes one module file per device that exists,
named by role (``telescope``, ``camera``, ``roof``/``dome``, ``focuser``, ``filters``, ...; a number
only where a role has several), the site, the comm (``embedded``: all modules in one process,
``nightcrew run DIR/*.yaml``; ``xmpp``: one process each under ``nightcrew up``, an account and a
random password per module in secrets/, mode 0600, and an access policy), and the robotic modules
the devices allow (weather verdict, scheduler with its task archive, mastermind, watchdog, focus,
flats, console). Asks for what the flags do not say, with defaults in brackets;
``--non-interactive`` never asks. A non-empty DIR is refused unless ``--force``. Nothing is written
when discovery fails. docs/observatory.md is the walk-through.
"""

from __future__ import annotations

import argparse
import asyncio
import secrets
from pathlib import Path
from typing import Any

from nightcrew.errors import ConfigError

__all__ = ["add_parser"]

#: (option, prompt, default) asked in this order when not given; None: no default (an answer is needed).
_QUESTIONS: tuple[tuple[str, str, str | None], ...] = (
    ("latitude", "Latitude, degrees north", None),
    ("longitude", "Longitude, degrees east", None),
    ("elevation", "Elevation, metres", "0"),
    ("site_name", "Name of the site", ""),
    ("timezone", "Time zone", "UTC"),
    ("horizon", "Lowest telescope altitude, degrees", "15"),
    ("comm", "Comm: embedded (one process) or xmpp (one per module)", "xmpp"),
)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "init",
        help="write an observatory directory for your devices",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    parser.add_argument("directory", type=Path, metavar="DIR")
    found = parser.add_argument_group("devices")
    found.add_argument(
        "--alpaca", action="append", default=[], metavar="URL", help="an Alpaca server (http://host:port)"
    )
    found.add_argument("--alpaca-discovery", action="store_true", help="find Alpaca servers by UDP discovery")
    found.add_argument(
        "--alpaca-address", default="255.255.255.255", help="where discovery asks (%(default)s)"
    )
    found.add_argument("--indi", action="append", default=[], metavar="HOST:PORT", help="an indiserver")
    site = parser.add_argument_group("site")
    site.add_argument("--latitude", type=float, help="degrees north")
    site.add_argument("--longitude", type=float, help="degrees east")
    site.add_argument("--elevation", type=float, help="metres (0)")
    site.add_argument("--site-name", help="the site's name")
    site.add_argument("--timezone", help="IANA time zone, e.g. Europe/Berlin (UTC)")
    site.add_argument("--horizon", type=float, help="lowest telescope altitude, degrees (15)")
    comm = parser.add_argument_group("comm")
    comm.add_argument("--comm", choices=("embedded", "xmpp"), help="how the modules talk (xmpp)")
    comm.add_argument("--xmpp-server", default="127.0.0.1:5222", help="the XMPP server (%(default)s)")
    comm.add_argument("--domain", default="observatory.local", help="the accounts' XMPP domain (%(default)s)")
    comm.add_argument("--room", default="nightcrew", help="the modules' room (%(default)s)")
    comm.add_argument("--ca-file", default="", help="the server's certificate (xmpp/certs/DOMAIN.crt in DIR)")
    more = parser.add_argument_group("more")
    more.add_argument("--images", default="images", help="where frames go, relative to DIR (%(default)s)")
    more.add_argument("--console-port", type=int, default=37180, help="web console port (%(default)s)")
    more.add_argument(
        "--good-weather-after",
        type=float,
        default=900.0,
        help="seconds of good weather before opening (%(default)s)",
    )
    parser.add_argument(
        "--non-interactive", action="store_true", help="never ask; missing answers are errors"
    )
    parser.add_argument(
        "--force", action="store_true", help="write into a non-empty DIR (same-named files replaced)"
    )
    parser.set_defaults(func=_init_command)
    return parser


def _init_command(args: argparse.Namespace) -> int:
    from nightcrew.night.init import (
        InitOptions,
        find_devices,
        name_by_role,
        observatory_files,
        write_directory,
    )

    answers = _answers(args)
    options = InitOptions(
        latitude=float(answers["latitude"]),
        longitude=float(answers["longitude"]),
        elevation=float(answers["elevation"]),
        site_name=str(answers["site_name"]),
        timezone=str(answers["timezone"]),
        horizon=float(answers["horizon"]),
        comm=answers["comm"],
        xmpp_server=args.xmpp_server,
        domain=args.domain,
        room=args.room,
        ca_file=args.ca_file,
        images=args.images,
        console_port=args.console_port,
        good_weather_after=args.good_weather_after,
    )
    if args.directory.is_dir() and any(args.directory.iterdir()) and not args.force:
        raise ConfigError(f"{args.directory} is not empty; use --force to write into it")
    found = asyncio.run(
        find_devices(
            args.alpaca, args.indi, alpaca_discovery=args.alpaca_discovery, address=args.alpaca_address
        )
    )
    devices = name_by_role(found)
    layout = observatory_files(options, devices, lambda _name: secrets.token_urlsafe(24))
    write_directory(args.directory, layout.files, force=args.force)
    print(f"wrote {args.directory}: {', '.join(layout.modules)}")
    for module, why in layout.left_out.items():
        print(f"  no {module}: {why}")
    steps = ["nightcrew check .", "nightcrew run *.yaml"]
    if options.comm == "xmpp":
        steps = [
            "nightcrew server init xmpp *.yaml",
            "nightcrew server start xmpp",
            "nightcrew check .",
            "nightcrew up .",
        ]
    print(f"next (docs/observatory.md): cd {args.directory} && {' && '.join(steps)}")
    return 0


def _answers(args: argparse.Namespace) -> dict[str, Any]:
    answers: dict[str, Any] = {}
    for key, prompt, default in _QUESTIONS:
        given = getattr(args, key)
        if given is not None:
            answers[key] = given
        elif args.non_interactive:
            if default is None:
                raise ConfigError(f"--{key.replace('_', '-')} is needed with --non-interactive")
            answers[key] = default
        else:
            answers[key] = _ask(prompt, default)
    if not (args.alpaca or args.alpaca_discovery or args.indi):
        if args.non_interactive:
            raise ConfigError(
                "name the devices' servers: --alpaca URL, --alpaca-discovery or --indi HOST:PORT"
            )
        urls = _ask(
            "Alpaca servers (URLs separated by spaces; 'discover' to search the network; '-' none)",
            "discover",
        )
        args.alpaca_discovery = urls.strip() == "discover"
        args.alpaca = [] if args.alpaca_discovery or urls.strip() == "-" else urls.split()
        indi = _ask("INDI servers (HOST:PORT separated by spaces; '-' none)", "-")
        args.indi = [] if indi.strip() == "-" else indi.split()
    return answers


def _ask(prompt: str, default: str | None) -> str:
    """One answer from the terminal; the default for an empty line; asks again while none is given."""
    for _ in range(10):
        shown = f" [{default}]" if default else ""
        try:
            reply = input(f"{prompt}{shown}: ").strip()
        except EOFError:
            raise ConfigError(f"no answer for '{prompt}' (use the flags and --non-interactive)") from None
        if reply:
            return reply
        if default is not None:
            return default
    raise ConfigError(f"no answer for '{prompt}'")
