"""Building the simulated observatory in one process, and ending its night safely.

:func:`build_observatory` builds every top-level module file of a directory (by default the
bundled :func:`bundled_observatory`) on a private in-process network, all sharing one clock and
one VFS whose ``images`` root is the output directory (:func:`images_vfs`, made and closed by the
caller, after the modules); :func:`observatory_site` reads its site.
:func:`park_and_close` is how every night ends: telescope parked and roof closed at once.
"""

from __future__ import annotations

import asyncio
import logging
import os
from collections.abc import Collection, Mapping
from pathlib import Path
from typing import Any

from nightcrew.clock import Clock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.config import ConfigNode, build_object, load_config, to_plain, validate_config
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.interfaces import IRoof, ITelescope
from nightcrew.modules import Module
from nightcrew.site import Site
from nightcrew.vfs import LocalFile, VirtualFileSystem

__all__ = [
    "DATA_VARIABLE",
    "FRAMES",
    "IMAGES_ROOT",
    "IN_PROCESS_KEYS",
    "SIM_RPC_GRACE",
    "build_observatory",
    "bundled_observatory",
    "data_environ",
    "files_environ",
    "images_vfs",
    "load_in_process",
    "observatory_site",
    "options_directory",
    "park_and_close",
]

log = logging.getLogger(__name__)

#: The VFS root the camera writes to (``filename_pattern: /images/...`` in camera.yaml).
IMAGES_ROOT = "images"
#: Wall seconds a call on the simulated observatory's network may take beyond its timeout: on a
#: fast clock a 10-s timeout is a few wall ms, less than rendering or analysing a frame under load.
SIM_RPC_GRACE = 1.0
#: The frames' directory in a night's output directory (camera.yaml: $OBSERVATORY_DATA/frames).
FRAMES = "frames"
#: The folder of the module files that options of ``nightcrew sim`` add (see options_directory).
OPTIONS = "options"
#: The variable the observatory's files read for where its data go (task archive, event record).
DATA_VARIABLE = "OBSERVATORY_DATA"
#: Module names the night needs (the file names of the bundled observatory).
TELESCOPE, ROOF, CAMERA, FOCUSER, FILTERS = "telescope", "roof", "camera", "focuser", "filters"


def bundled_observatory() -> Path:
    """The directory of the bundled observatory's configuration files (package data)."""
    return Path(__file__).resolve().with_name("observatory")


#: What one process gives every module in place of its file's: the in-process comm. The files'
#: ``comm`` (XMPP for ``nightcrew up``, with a password from ``secrets/`` that ``nightcrew server
#: init`` makes) is not read at all, so the files load where no server was ever set up.
IN_PROCESS_KEYS = ("comm",)


def files_environ() -> dict[str, str]:
    """The environment the observatory's files are read in when their modules run in one process."""
    return dict(os.environ)


def load_in_process(path: Path, environ: Mapping[str, str] | None = None) -> ConfigNode:
    """A module file as one process reads it: without the keys of :data:`IN_PROCESS_KEYS`;
    ``environ``: the placeholders' values (default: :func:`files_environ`)."""
    values = files_environ() if environ is None else environ
    return load_config(path, environ=values, skip_keys=IN_PROCESS_KEYS)


def data_environ(out: Path) -> dict[str, str]:
    """The environment the observatory's files are read in for a night into ``out``: its data
    (``$OBSERVATORY_DATA``: task archive, event record) go there."""
    return {**files_environ(), DATA_VARIABLE: str(out.resolve())}


def options_directory(directory: Path) -> Path:
    """Where the module files of ``nightcrew sim``'s options (``--indi``, ``--console``,
    ``--archive``) are: ``options/`` of ``directory``, else of the bundled observatory."""
    own = directory / OPTIONS
    return own if own.is_dir() else bundled_observatory() / OPTIONS


def images_vfs(frames: Path) -> VirtualFileSystem:
    """The observatory's VFS: its ``images`` root in ``frames``. The caller closes it."""
    return VirtualFileSystem({IMAGES_ROOT: LocalFile(str(frames))})


def observatory_site(directory: Path) -> Site:
    """The observatory's site: the one the telescope's file gives."""
    path = directory / "telescope.yaml"
    if not path.is_file():
        raise ConfigError(f"no telescope.yaml in {directory}: the night needs a telescope")
    site = load_in_process(path).get("site")
    if not isinstance(site, dict):
        raise ConfigError("the telescope needs a site (latitude, longitude, elevation)", file=str(path))
    try:
        return Site(**to_plain(site))
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"invalid site: {exc}", file=str(path), key="site") from exc


def build_observatory(
    directory: Path,
    *,
    clock: Clock,
    vfs: VirtualFileSystem,
    seed: int | None = None,
    network: LocalNetwork,
    overrides: Mapping[str, Mapping[str, Any]] | None = None,
    environ: Mapping[str, str] | None = None,
    names: Collection[str] | None = None,
) -> list[Module]:
    """Validate, then build the modules of the top-level ``*.yaml`` files of ``directory``.

    Every module gets ``clock``, ``vfs`` unless its file names one (shared, not closed by the
    modules: the caller closes it after them) and a comm on ``network`` named after its file;
    ``seed`` replaces the seed of every file that sets one, and ``overrides`` (by module name)
    replace keys after validation (objects the file cannot say); ``environ`` gives the files'
    ``${NAME}`` placeholders (default: :func:`files_environ`); ``names``: only the files with these
    stems. Nothing is opened. Files in subdirectories (fragments, extras, options) are not
    modules of the night.
    """
    paths = sorted(p for p in directory.glob("*.yaml") if names is None or p.stem in names)
    if not paths:
        raise ConfigError(f"no module files (*.yaml) in {directory}")
    configs = [load_in_process(path, environ or None) for path in paths]
    for config in configs:
        validate_config(config, Module)
    modules = []
    for path, config in zip(paths, configs, strict=True):
        given: dict[str, Any] = {"comm": LocalComm(path.stem, network=network), "clock": clock}
        if "vfs" not in config:  # a module that names its own file system keeps it
            given["vfs"] = vfs
        if seed is not None and "seed" in config:
            given["seed"] = seed
        given.update((overrides or {}).get(path.stem, {}))
        config.update(given)
        modules.append(build_object(config, Module))
    return modules


async def park_and_close(driver: Module) -> None:
    """Park the telescope and close the roof at the same time; log (never raise) failures."""
    proxy = driver.comm.proxy

    async def park() -> None:
        await (await proxy(TELESCOPE, ITelescope)).park()

    async def close_roof() -> None:
        await (await proxy(ROOF, IRoof)).close_roof()

    results = await asyncio.gather(park(), close_roof(), return_exceptions=True)
    for what, result in zip(("park the telescope", "close the roof"), results, strict=True):
        if isinstance(result, NightcrewError):
            log.error("could not %s: %s", what, result)
        elif isinstance(result, BaseException):
            raise result
