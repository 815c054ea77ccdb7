"""The module files of one observatory by module name, for ``nightcrew check``'s checks across files."""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

from nightcrew.config import load_config, to_plain
from nightcrew.errors import ConfigError

__all__ = ["module_configs"]


def module_configs(files: Iterable[Path]) -> dict[str, tuple[Path, dict[str, Any]]]:
    """Module name (``name``, else the file's stem) → (file, plain config) of every module file
    among ``files``; files that do not load are left out (their own check reports them)."""
    modules: dict[str, tuple[Path, dict[str, Any]]] = {}
    for path in files:
        try:
            config = to_plain(load_config(path))
        except ConfigError:
            continue
        if isinstance(config, dict) and "class" in config:
            modules[str(config.get("name") or path.stem)] = (path, config)
    return modules
