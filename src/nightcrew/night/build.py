"""Running the bundled simulated observatory through one night, in one process.

:func:`build_observatory` builds every top-level module file of a directory (by default the
bundled :func:`bundled_observatory`) on a private in-process network, all sharing one clock and
one VFS whose ``images`` root is the output directory. :func:`run_night` opens them, runs the
steps of :func:`~nightcrew.night.fields.plan_night` through proxies - exactly as a
script would drive real devices - and always ends safely: telescope parked and roof closed (also
on an error or when ``stop`` is set), then every module closed.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from datetime import datetime
from pathlib import Path
from typing import Any

from nightcrew.clock import Clock
from nightcrew.comm.local import LocalComm, LocalNetwork
from nightcrew.config import build_object, load_config, validate_config
from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.interfaces import (
    ICamera,
    IExposureTime,
    IFilters,
    IFocuser,
    IImageType,
    IRoof,
    ITelescope,
)
from nightcrew.modules import Module
from nightcrew.modules.sim.interfaces import ISimFocuserTruth
from nightcrew.night.fields import Step
from nightcrew.vfs import LocalFile, VirtualFileSystem

__all__ = [
    "IMAGES_ROOT",
    "SIM_RPC_GRACE",
    "NightReport",
    "build_observatory",
    "bundled_observatory",
    "park_and_close",
    "run_night",
]

log = logging.getLogger(__name__)

#: The VFS root the camera writes to (``filename_pattern: /images/...`` in camera.yaml).
IMAGES_ROOT = "images"
#: Wall seconds a call on the simulated observatory's network may take beyond its timeout: on a
#: fast clock a 10-s timeout is a few wall ms, less than rendering or analysing a frame under load.
SIM_RPC_GRACE = 1.0
#: Module names the night needs (the file names of the bundled observatory).
TELESCOPE, ROOF, CAMERA, FOCUSER, FILTERS = "telescope", "roof", "camera", "focuser", "filters"

#: Called before each step with (step number from 1, number of steps, the step, clock time).
ProgressCallback = Callable[[int, int, Step, datetime], None]


def bundled_observatory() -> Path:
    """The directory of the bundled observatory's configuration files (package data)."""
    return Path(__file__).resolve().with_name("observatory")


@dataclass
class NightReport:
    """What a night produced: the images' VFS paths and files, and whether it ran to its end."""

    frames: list[str] = field(default_factory=list)
    files: list[Path] = field(default_factory=list)
    completed: bool = False


def build_observatory(
    directory: Path,
    *,
    clock: Clock,
    out_dir: Path,
    seed: int | None = None,
    network: LocalNetwork,
    overrides: Mapping[str, Mapping[str, Any]] | None = None,
) -> list[Module]:
    """Validate, then build the modules of the top-level ``*.yaml`` files of ``directory``.

    Every module gets ``clock``, a VFS with the ``images`` root in ``out_dir`` and a comm on
    ``network`` named after its file; ``seed`` replaces the seed of every file that sets one, and
    ``overrides`` (by module name) replace keys after validation (objects the file cannot say).
    Nothing is opened. Files in subdirectories (fragments, extras) are not modules of the night.
    """
    paths = sorted(directory.glob("*.yaml"))
    if not paths:
        raise ConfigError(f"no module files (*.yaml) in {directory}")
    configs = [load_config(path) for path in paths]
    for config in configs:
        validate_config(config, Module)
    vfs = VirtualFileSystem({IMAGES_ROOT: LocalFile(str(out_dir))})
    modules = []
    for path, config in zip(paths, configs, strict=True):
        given: dict[str, Any] = {
            "comm": LocalComm(path.stem, network=network),
            "clock": clock,
            "vfs": vfs,
        }
        if seed is not None and "seed" in config:
            given["seed"] = seed
        given.update((overrides or {}).get(path.stem, {}))
        config.update(given)
        modules.append(build_object(config, Module))
    return modules


async def run_night(
    modules: list[Module],
    steps: list[Step],
    *,
    clock: Clock,
    network: LocalNetwork,
    out_dir: Path,
    progress: ProgressCallback | None = None,
    stop: asyncio.Event | None = None,
) -> NightReport:
    """Open ``modules``, run ``steps`` (the last, ``shutdown``, always runs), close everything.

    Raises:
        NightcrewError: a step failed (after the safe shutdown).
    """
    report = NightReport()
    driver = Module(comm=LocalComm("night", network=network), clock=clock)
    opened: list[Module] = []
    try:
        for module in [*modules, driver]:
            await module.open()
            opened.append(module)
        night = _Night(driver, report, out_dir)
        total = len(steps)
        work = asyncio.create_task(night.run([s for s in steps if s.action != "shutdown"], progress, total))
        stopped = asyncio.create_task((stop or asyncio.Event()).wait())
        try:
            await asyncio.wait([work, stopped], return_when=asyncio.FIRST_COMPLETED)
        finally:
            for task in (work, stopped):
                task.cancel()
            await asyncio.gather(work, stopped, return_exceptions=True)
            if progress is not None:
                progress(total, total, steps[-1], clock.now())
            await night.shutdown()
        if not work.cancelled():
            work.result()  # re-raise a failed step
            report.completed = True
        else:
            log.warning("night stopped early after %d frames", len(report.frames))
    finally:
        for module in reversed(opened):
            await module.close()
    return report


class _Night:
    """Runs steps against the devices, through proxies from the ``driver`` module."""

    def __init__(self, driver: Module, report: NightReport, out_dir: Path) -> None:
        self._driver = driver
        self._report = report
        self._out_dir = out_dir

    async def run(self, steps: list[Step], progress: ProgressCallback | None, total: int) -> None:
        for number, step in enumerate(steps, start=1):
            if progress is not None:
                progress(number, total, step, self._driver.clock.now())
            log.info("step %d/%d: %s", number, total, step.describe())
            await self._do(step)

    async def _do(self, step: Step) -> None:
        proxy = self._driver.comm.proxy
        if step.action == "prepare":
            await asyncio.gather(
                (await proxy(ROOF, IRoof)).open_roof(), (await proxy(TELESCOPE, ITelescope)).init()
            )
            for name, interface in ((FOCUSER, IFocuser), (FILTERS, IFilters)):
                if await self._online(name):
                    await (await proxy(name, interface)).init()
        elif step.action == "focus":
            if await self._online(FOCUSER):
                # Stand-in for an autofocus run: the simulator tells where the best focus is.
                best = await (await proxy(FOCUSER, ISimFocuserTruth)).get_best_focus()
                await (await proxy(FOCUSER, IFocuser)).set_focus(round(best, 3))
        elif step.action == "slew" and step.target is not None:
            await (await proxy(TELESCOPE, ITelescope)).move_radec(step.target.ra, step.target.dec)
        elif step.action == "expose":
            await self._expose(step)

    async def _expose(self, step: Step) -> None:
        proxy = self._driver.comm.proxy
        if step.filter_name is not None:
            await (await proxy(FILTERS, IFilters)).set_filter(step.filter_name)
        await (await proxy(CAMERA, IExposureTime)).set_exposure_time(step.exposure_time)
        await (await proxy(CAMERA, IImageType)).set_image_type(step.image_type)
        filename = await (await proxy(CAMERA, ICamera)).grab_data()
        self._report.frames.append(filename)
        self._report.files.append(self._out_dir / filename.removeprefix(f"/{IMAGES_ROOT}/"))

    async def _online(self, name: str) -> bool:
        return name in self._driver.comm.clients

    async def shutdown(self) -> None:
        await park_and_close(self._driver)


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
