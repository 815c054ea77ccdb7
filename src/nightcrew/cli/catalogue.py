"""``nightcrew catalogue [--output FILE] [--check FILE] [--js DIR]``: the machine-readable catalogue.

Every interface as an OpenRPC document (methods, parameters as JSON Schema with units, bounds,
defaults and enum values, results, announced timeouts, docstrings), every event's JSON fields as
JSON Schema, and every error class. Printed as JSON; ``--output`` writes it to a file (the repo
keeps docs/catalogue.json), ``--check`` exits 1 when a file differs from what the code gives, and
``--js`` writes the generated part of the JavaScript client (the repo keeps clients/js/generated).
"""

from __future__ import annotations

import argparse
import importlib
import json
import logging
import pkgutil
import sys
from pathlib import Path
from typing import Any, TypeVar

import nightcrew
from nightcrew.cli.catalogue_js import js_client_files
from nightcrew.comm.catalogue import build_catalogue
from nightcrew.errors import NightcrewError
from nightcrew.events.base import Event
from nightcrew.interfaces.base import Interface, is_interface

__all__ = ["add_parser", "catalogue_text", "nightcrew_classes", "write_js_client"]

log = logging.getLogger(__name__)

T = TypeVar("T")


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "catalogue",
        help="print the catalogue of interfaces, events and errors",
        description=__doc__.split("\n\n", 1)[1],
    )
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--output", type=Path, metavar="FILE", help="write the catalogue to FILE")
    group.add_argument(
        "--check", type=Path, metavar="FILE", help="exit 1 if FILE is not the current catalogue"
    )
    group.add_argument(
        "--js", type=Path, metavar="DIR", help="write the generated JavaScript client files to DIR"
    )
    parser.set_defaults(func=_command)
    return parser


def _import_all_of_nightcrew() -> None:
    """Import every module of the package, so every interface, event and error class is defined."""
    for info in pkgutil.walk_packages(nightcrew.__path__, "nightcrew."):
        if info.name.rsplit(".", 1)[-1] != "__main__":
            importlib.import_module(info.name)


def nightcrew_classes(base: type[T]) -> list[type[T]]:
    """Every class derived from ``base`` that nightcrew itself defines (not tests or plugins), by name."""
    _import_all_of_nightcrew()
    found: dict[str, type[T]] = {}
    pending = list(base.__subclasses__())
    while pending:
        cls = pending.pop()
        pending += cls.__subclasses__()
        if cls.__module__.startswith("nightcrew."):
            found[cls.__name__] = cls
    return [found[name] for name in sorted(found)]


def catalogue_text() -> str:
    """The catalogue as the committed file holds it: sorted keys, two-space indents, final newline."""
    interfaces = [cls for cls in nightcrew_classes(Interface) if is_interface(cls)]
    errors: list[type[NightcrewError]] = [NightcrewError, *nightcrew_classes(NightcrewError)]
    catalogue = build_catalogue(interfaces, nightcrew_classes(Event), errors)
    return json.dumps(catalogue, indent=2, sort_keys=True, ensure_ascii=False) + "\n"


def write_js_client(directory: Path, text: str) -> None:
    """Write the JavaScript client generated from catalogue ``text`` into ``directory``.

    Generated files no longer made (an interface that was removed) are deleted, so ``directory``
    holds exactly what the catalogue gives.
    """
    files = js_client_files(json.loads(text))
    for stale in directory.rglob("*.js") if directory.is_dir() else []:
        if stale.relative_to(directory).as_posix() not in files:
            stale.unlink()
    for relative, content in files.items():
        path = directory / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(content, encoding="utf-8")


def _command(args: argparse.Namespace) -> int:
    text = catalogue_text()
    if args.js is not None:
        write_js_client(args.js, text)
        return 0
    if args.output is not None:
        args.output.write_text(text, encoding="utf-8")
        return 0
    if args.check is not None:
        try:
            current = args.check.read_text(encoding="utf-8")
        except OSError as exc:
            print(f"{args.check}: cannot read: {exc.strerror}", file=sys.stderr)
            return 1
        if current != text:
            print(f"{args.check} is stale: run `nightcrew catalogue --output {args.check}`", file=sys.stderr)
            return 1
        return 0
    sys.stdout.write(text)
    return 0
