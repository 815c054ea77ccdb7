"""``nightcrew run FILE.yaml [FILE.yaml ...]``: run modules in this process until stopped.

Every file is validated before any module is built, and every module is built before any is
opened, so a bad configuration stops the start with one message and nothing half-started.
A module without a ``comm`` is named after its file (``camera.yaml`` → ``camera``) and reaches
the other modules of this process. SIGINT (Ctrl-C) and SIGTERM close all modules cleanly. A module
whose comm is lost for good (another process logged in with its account) closes all modules and
ends the command with that error (exit 1), so that a supervisor sees it and nothing stays offline.
"""

from __future__ import annotations

import argparse
import asyncio
import logging
import os
from pathlib import Path
from typing import Any

from nightcrew.cli._running import stop_on_signals
from nightcrew.config import ConfigNode, build_object, load_config, validate_config
from nightcrew.config._classes import import_class
from nightcrew.errors import NightcrewError
from nightcrew.modules import Module
from nightcrew.supervisor import heartbeat_loop

__all__ = ["add_parser", "build_described", "build_file", "build_modules", "run_modules"]

log = logging.getLogger(__name__)


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "run", help="run modules described by YAML files", description=__doc__.split("\n\n", 1)[1]
    )
    parser.add_argument("configs", nargs="+", metavar="FILE.yaml", help="module configuration files")
    parser.set_defaults(func=_run_command)
    return parser


def build_modules(paths: list[str]) -> list[Module]:
    """Load and validate all files, then build their modules (nothing is opened)."""
    configs = [load_config(path) for path in paths]
    for config in configs:
        validate_config(config, Module)
    return [build_described(path, config, Module) for path, config in zip(paths, configs, strict=True)]


def build_file(path: str | os.PathLike[str], expected: type | None = Module) -> Any:
    """Load, validate and build the object one file describes, as ``run`` does; nothing is opened.

    ``nightcrew check`` calls this, so its verdict includes the constructors' own checks.
    """
    config = load_config(path)
    validate_config(config, expected)
    return build_described(path, config, expected)


def build_described(path: str | os.PathLike[str], config: ConfigNode, expected: type | None) -> Any:
    """Build a validated description; a module without ``name`` or ``comm`` is named after its file."""
    if "name" not in config and "comm" not in config and issubclass(import_class(config["class"]), Module):
        config["name"] = Path(path).stem
    return build_object(config, expected)


async def run_modules(modules: list[Module], stop: asyncio.Event | None = None) -> None:
    """Open ``modules``, wait until ``stop`` is set (or a signal arrives), then close them.

    Raises the error of a comm lost for good (after closing every module).
    """
    fatal: list[NightcrewError] = []
    opened: list[Module] = []
    # Under `nightcrew up`: the beat that tells the supervisor this process's event loop runs; it
    # goes on while modules close (a roof may take minutes to park).
    heartbeat = asyncio.get_running_loop().create_task(heartbeat_loop(), name="supervisor heartbeat")
    try:
        async with stop_on_signals(stop) as stopped:

            def on_fatal(error: NightcrewError) -> None:
                fatal.append(error)
                stopped.set()

            for module in modules:
                module.comm.on_fatal = on_fatal
            try:
                for module in modules:
                    await module.open()
                    opened.append(module)
                await stopped.wait()
                log.info("stopping")
            finally:
                for module in reversed(opened):
                    try:
                        await module.close()
                    except NightcrewError as exc:
                        if not fatal:
                            raise
                        # Its comm is gone for good: a failing goodbye must not hide why we stop.
                        log.warning("%s closed with an error: %s", module.name, exc)
    finally:
        heartbeat.cancel()
        await asyncio.gather(heartbeat, return_exceptions=True)
    if fatal:
        raise fatal[0]


def _run_command(args: argparse.Namespace) -> int:
    modules = build_modules(args.configs)
    asyncio.run(run_modules(modules))
    return 0
