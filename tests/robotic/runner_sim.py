"""A small simulated observatory for runner and script tests: modules on a LocalNetwork, fast clock."""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator
from typing import Any

import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.clock import Clock
from nightcrew.events import NewImageEvent
from nightcrew.modules import Module
from nightcrew.modules.sim import SimCamera, SimFilterWheel, SimFocuser, SimRoof, SimTelescope
from nightcrew.robotic.runner import Script, TaskRunner
from nightcrew.robotic.tasks import Task, TaskProgress, parse_request_group, tasks_of_group
from nightcrew.testing import Observatory
from nightcrew.vfs import MemoryFile

__all__ = ["PLEIADES", "ProgressLog", "SimSetup", "make_task", "request_group", "sim", "start_sim"]

PLEIADES = {"name": "Pleiades", "ra": 56.75, "dec": 24.12}  # high in the sky at the conftest epoch
#: A 256² chip: frames render in milliseconds; binned 2x2 they are 128².
DETECTOR = {"chip_width": 256, "chip_height": 256, "cosmic_rays_per_s": 0.0}


class ProgressLog:
    """A progress callback that keeps every report, and the clock time of each if given a clock."""

    def __init__(self, clock: Clock | None = None) -> None:
        self.reports: list[TaskProgress] = []
        self.times: list[float] = []
        self._clock = clock

    async def __call__(self, progress: TaskProgress) -> None:
        self.reports.append(progress)
        if self._clock is not None:
            self.times.append(self._clock.time())

    @property
    def last(self) -> TaskProgress:
        return self.reports[-1]


class SimSetup:
    """Telescope, camera, filter wheel, focuser and roof, plus a host module for the runner."""

    def __init__(self, obs: Observatory, host: Module, camera: SimCamera, telescope: SimTelescope) -> None:
        self.obs, self.host, self.camera, self.telescope = obs, host, camera, telescope
        self.frames: list[str] = []  # VFS paths from NewImageEvents, in order

    async def on_new_image(self, event: NewImageEvent, sender: str) -> bool:
        self.frames.append(event.filename)
        return True

    async def runner(self, scripts: dict[str, Script | dict[str, Any]]) -> TaskRunner:
        """A runner added to the host module as the mastermind does, and opened."""
        runner = self.host.add_child(TaskRunner(scripts=scripts))
        await runner.open()
        return runner

    async def read(self, filename: str) -> fits.Header:
        return (await self.obs.vfs.read_fits(filename))[0].header

    async def headers(self, count: int) -> list[fits.Header]:
        """Headers of the first ``count`` frames announced (events arrive a moment after the call)."""
        for _ in range(500):
            if len(self.frames) >= count:
                break
            await asyncio.sleep(0.01)
        assert len(self.frames) == count, self.frames
        return [await self.read(filename) for filename in self.frames]


async def start_sim(
    obs: Observatory,
    *,
    roof_open: bool = True,
    telescope_options: dict[str, Any] | None = None,
    **camera: Any,
) -> SimSetup:
    telescope = await obs.start(
        SimTelescope, "telescope", init_time=0.0, settle_time=1.0, seed=1, **(telescope_options or {})
    )
    await obs.start(SimFocuser, "focuser", focus=25.0, best_focus=25.0)
    await obs.start(SimFilterWheel, "filters", filters=["V", "R"], filter_name="V")
    roof = await obs.start(SimRoof, "roof", open_time=1.0)
    await telescope.init()
    if roof_open:
        await roof.open_roof()
    options: dict[str, Any] = {
        "detector": DETECTOR,
        "catalog_depth": 14.0,
        "seed": 3,
        "readout_time": 0.5,
        "weather": None,
        **camera,
    }
    cam = await obs.start(SimCamera, "camera", **options)
    await cam.grab_data()  # the first frame loads the star field: keep that out of the tests' timing
    host = await obs.start(Module, "robotic")
    setup = SimSetup(obs, host, cam, telescope)
    await host.comm.register_event(NewImageEvent, setup.on_new_image)
    return setup


@pytest.fixture
async def sim() -> AsyncIterator[SimSetup]:
    obs = Observatory()
    try:
        yield await start_sim(obs)
    finally:
        await obs.close()
        MemoryFile.clear_shared()


def request_group(*configurations: dict[str, Any]) -> dict[str, Any]:
    """Plain data of a group of one request with ``configurations``, the night of the tests."""
    return {
        "name": "runner test",
        "proposal": "tests",
        "requests": [
            {
                "location": {"telescope_class": "0m4"},
                "windows": [{"start": "2024-01-15T18:00:00Z", "end": "2024-01-16T06:00:00Z"}],
                "configurations": list(configurations),
            }
        ],
    }


def make_task(*configurations: dict[str, Any], task_id: str = "t1") -> Task:
    """A task of one request with ``configurations`` (plain data as in a request group file)."""
    group = parse_request_group(request_group(*configurations))
    return tasks_of_group(group, "g1", [task_id])[0]
