"""Which files of a directory are module configurations, each under the name the supervisor uses.

The files are those ``nightcrew check DIR`` checks (fragments that others include left out); of
those, a file whose ``class`` is a Module is a module, named after its file (``roof.yaml`` →
``roof``). A file that is not a module (an operator's comm description, a clock) is skipped. A file
that cannot be read or names no importable class is still listed, with its error: it may well be a
module with a typo, and the operator must see it in ``nightcrew status``. Files in a folder
``options/`` are left out: module files one adds on request, as ``nightcrew sim --indi`` or
``--console`` does from the bundled observatory's ``options/``, not modules of the observatory.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path

from nightcrew.config import config_files, load_config
from nightcrew.config._classes import ClassResolutionError, import_class
from nightcrew.errors import ConfigError

__all__ = ["ModuleFile", "module_files"]

log = logging.getLogger(__name__)

#: The folder of module files that are not started (see the module doc).
OPTIONS = "options"


@dataclass(frozen=True)
class ModuleFile:
    """A module configuration file; ``error`` says why it cannot be started, if it cannot."""

    name: str
    path: Path
    error: str | None = None


def module_files(directory: Path) -> list[ModuleFile]:
    """The module files in ``directory``; ConfigError if it is not a directory or holds none."""
    if not directory.is_dir():
        raise ConfigError(f"{directory} is not a directory of module configurations")
    from nightcrew.modules import Module

    found: dict[str, ModuleFile] = {}
    for path in config_files([directory]):
        if OPTIONS in path.relative_to(directory).parts[:-1]:
            continue
        name = path.stem
        if name in found:
            raise ConfigError(f"two module files named '{name}': {found[name].path} and {path}")
        try:
            cls = import_class(str(load_config(path).get("class", "")))
        except ConfigError as exc:
            found[name] = ModuleFile(name, path, str(exc))
            continue
        except ClassResolutionError as exc:
            found[name] = ModuleFile(name, path, f"{path}: {exc}")
            continue
        if issubclass(cls, Module):
            found[name] = ModuleFile(name, path)
        else:
            log.debug("%s is not a module (%s); not started", path, cls.__name__)
    if not found:
        raise ConfigError(f"no module configurations in {directory}")
    return list(found.values())
