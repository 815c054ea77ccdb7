"""Which files to check when a directory is named.

A directory stands for every ``*.yaml`` / ``*.yml`` file below it, recursively (hidden directories
skipped), minus *fragments*: files that another file found there includes. A fragment (say a shared
``comm.yaml``) is usually not a complete module description on its own; it is checked as part of
every file that includes it. Files named explicitly are always checked.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterable, Mapping
from pathlib import Path

from nightcrew.config._loader import load_file
from nightcrew.errors import ConfigError

__all__ = ["config_files"]

_SUFFIXES = (".yaml", ".yml")


def config_files(
    paths: Iterable[str | os.PathLike[str]], environ: Mapping[str, str] | None = None
) -> list[Path]:
    """The configuration files that ``paths`` (files and directories) stand for, in order."""
    files: list[Path] = []
    for path in map(Path, paths):
        if path.is_dir():
            files.extend(_top_level_files(path, environ))
        else:
            files.append(path)
    return files


def _top_level_files(directory: Path, environ: Mapping[str, str] | None) -> list[Path]:
    candidates = sorted(
        path
        for path in directory.rglob("*")
        if path.suffix in _SUFFIXES
        and path.is_file()
        and not any(part.startswith(".") for part in path.relative_to(directory).parts[:-1])
    )
    fragments: set[Path] = set()
    for path in candidates:
        with contextlib.suppress(ConfigError):  # reported when the file itself is checked
            fragments |= load_file(path, environ).included
    return [path for path in candidates if path.resolve() not in fragments]
