"""``nightcrew check PATH ...``: validate configuration files without starting anything.

Every module file is loaded, validated and built exactly as ``run`` builds it (constructor checks
and input files included; nothing is opened or connected), so the two agree on every file. A
directory stands for every ``*.yaml``/``*.yml`` below it (recursively), each checked as what it is:

- a file with ``class`` describes a module (or another object): built as ``run`` builds it;
- a request group (``requests``), or a list of them (``request_groups``), is a task file: validated
  as ``nightcrew tasks add`` validates it;
- an access policy (``roles``, ``accounts``) is read as the comms read it;
- a fragment (site, comm, secrets) that another file there includes is checked as part of the
  files that include it, not on its own.

Prints ``OK FILE`` for every valid file and one ``FILE:LINE: key 'x': message`` line (on stderr)
for every invalid one (a problem in a fragment once, naming the files that include it); a file of
none of these kinds is listed as ``SKIP FILE`` with the reason. The variables the files need and
the environment lacks are named on one line, with the files that read them. Across the files: a
camera's field the index files cannot solve, a cooling schedule's set point below what its
camera declares it can reach, a task's dither amplitude larger than the camera's field, an
acquisition's target pixel beyond its camera's chip, and a focus temperature source naming a module
that no file provides (or one without that kind of reading). Exits 0 when all are valid, else 2.
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

from nightcrew.cli.run import build_file
from nightcrew.config import config_files, load_data_file, unset_variable
from nightcrew.config._loader import load_file
from nightcrew.errors import ConfigError, NightcrewError

if TYPE_CHECKING:
    from nightcrew.robotic.tasks import RequestGroup

__all__ = ["add_parser", "check_file", "run_check"]

#: What a file that is not a module file is, by the keys at its top.
_TASKS, _POLICY = "task file", "access policy"


def add_parser(subparsers: Any) -> argparse.ArgumentParser:
    parser: argparse.ArgumentParser = subparsers.add_parser(
        "check",
        help="validate configuration files",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    parser.add_argument("paths", nargs="+", metavar="PATH", help="a YAML file, or a directory of them")
    parser.set_defaults(func=run_check)
    return parser


def check_file(path: Path) -> None:
    """Load, validate and build (without opening) what one file describes, exactly as ``run`` does.

    Building runs the constructors' own checks (ranges, combinations of keys), so a file ``check``
    calls OK is one ``run`` accepts. Raises :class:`ConfigError` for the first problem.
    """
    build_file(path, expected=None)


def file_kind(path: Path) -> str | None:
    """None for a module (or object) file; else what the file is (:data:`_TASKS`, :data:`_POLICY`),
    or ConfigError naming why it is none of these."""
    value = load_file(path).value
    if isinstance(value, Mapping) and "class" in value:
        return None
    if _is_task_data(value):
        return _TASKS
    if isinstance(value, Mapping) and ("roles" in value or "accounts" in value):
        return _POLICY
    raise _NotChecked(
        "neither a module file (no 'class'), a task file (no 'requests') nor an access policy "
        "(no 'roles'), and no file here includes it"
    )


def check_any(path: Path) -> str | None:
    """Check ``path`` as what it is (:func:`file_kind`); returns that kind (None: a module file)."""
    kind = file_kind(path)
    if kind is None:
        check_file(path)
    elif kind == _TASKS:
        _check_tasks(path)
    else:
        from nightcrew.security import load_policy

        load_policy(path)
    return kind


def run_check(args: argparse.Namespace) -> int:
    files = config_files(args.paths)
    if not files:
        print(f"nightcrew: error: no *.yaml files in {' '.join(args.paths)}", file=sys.stderr)
        return 2
    all_valid = True
    unset: dict[str, list[Path]] = {}  # variable -> files that need it
    # A problem in a fragment is told once, with the files that include it.
    in_fragments: dict[tuple[str, int | None, str], tuple[ConfigError, list[Path]]] = {}
    task_files: list[Path] = []
    for path in files:
        try:
            kind = check_any(path)
        except _NotChecked as exc:
            print(f"SKIP {path}: {exc}")
        except ConfigError as exc:
            if getattr(args, "debug", False):
                raise
            all_valid = False
            variable = unset_variable(exc.message)
            if variable is not None:
                unset.setdefault(variable, []).append(path)
            elif exc.file and os.path.normpath(exc.file) != os.path.normpath(path):
                in_fragments.setdefault((exc.file, exc.line, exc.message), (exc, []))[1].append(path)
            else:
                print(f"{path}: {exc}" if not exc.file else exc, file=sys.stderr)
        except NightcrewError as exc:  # a task file or a policy: their errors name the file
            if getattr(args, "debug", False):
                raise
            all_valid = False
            print(str(exc) if str(path) in str(exc) else f"{path}: {exc}", file=sys.stderr)
        else:
            print(f"OK {path}" + (f" ({kind})" if kind else ""))
            if kind == _TASKS:
                task_files.append(path)
    for problem, paths in in_fragments.values():
        print(f"{problem} (included from {_few(paths)})", file=sys.stderr)
    if unset:
        needed = "; ".join(f"{name} (for {_few(paths)})" for name, paths in unset.items())
        print(f"set {needed}", file=sys.stderr)
    from nightcrew.images.astrometry import observatory_coverage_problems  # astropy: only here

    for coverage in observatory_coverage_problems(files):  # a camera field the index files cannot solve
        print(f"nightcrew: error: {coverage}", file=sys.stderr)
        all_valid = False
    from nightcrew.modules.camera.cooling import cooling_reach_problems

    for reach in cooling_reach_problems(files):  # a set point colder than the camera can hold
        print(f"nightcrew: error: {reach}", file=sys.stderr)
        all_valid = False
    for dither in _dither_problems(task_files, files):  # a dither that leaves the field
        print(f"nightcrew: error: {dither}", file=sys.stderr)
        all_valid = False
    from nightcrew.modules.pointing.acquisition import target_pixel_problems

    for outside in target_pixel_problems(files):  # an acquisition's target pixel beyond its camera's chip
        print(f"nightcrew: error: {outside}", file=sys.stderr)
        all_valid = False
    from nightcrew.modules.focus.checks import temperature_source_problems

    for source in temperature_source_problems(files):  # a refocus temperature no module provides
        print(f"nightcrew: error: {source}", file=sys.stderr)
        all_valid = False
    return 0 if all_valid else 2


def _dither_problems(task_files: list[Path], files: list[Path]) -> list[str]:
    from nightcrew.images.astrometry import camera_fields_arcmin
    from nightcrew.robotic.scripts import dither_field_problems

    fields = camera_fields_arcmin(files)
    groups = [(f"{path}: {prefix}", group) for path in task_files for prefix, group in _task_groups(path)]
    return dither_field_problems(groups, min(fields) if fields else None)


def _few(paths: list[Path]) -> str:
    names = ", ".join(str(path) for path in paths[:2])
    return names + (f" and {len(paths) - 2} more" if len(paths) > 2 else "")


class _NotChecked(Exception):
    """A file that is none of the kinds ``check`` knows."""


def _is_task_data(value: object) -> bool:
    if isinstance(value, Mapping):
        return "requests" in value or set(value) == {"request_groups"}
    return isinstance(value, list) and bool(value) and all(_is_task_data(item) for item in value)


def _check_tasks(path: Path) -> None:
    """Validate a task file as ``nightcrew tasks add`` (one group) or a YAML archive (a list) reads it."""
    _task_groups(path)


def _task_groups(path: Path) -> list[tuple[str, RequestGroup]]:
    """The request groups of a task file, each with its prefix (``[1]`` in a list, else "")."""
    from nightcrew.robotic.tasks import parse_request_group

    data = load_data_file(path)
    if isinstance(data, Mapping) and "request_groups" in data:
        data = data["request_groups"]
    groups = data if isinstance(data, list) else [data]
    prefixes = [f"[{index}]" if isinstance(data, list) else "" for index in range(len(groups))]
    return [
        (prefix, parse_request_group(group, prefix=prefix, source=str(path)))
        for prefix, group in zip(prefixes, groups, strict=True)
    ]
