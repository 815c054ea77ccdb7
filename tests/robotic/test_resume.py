"""A task interrupted mid-way and run again takes only the missing exposures.

Real parts throughout: the TaskRunner with its scripts on the simulated observatory, progress
recorded in a real archive (SQLite and YAML) as the mastermind records it, and a real interruption
(the running task cancelled after some frames, as the mastermind does on bad weather).
"""

from __future__ import annotations

import asyncio
from collections.abc import AsyncIterator, Callable
from pathlib import Path
from typing import Any

import pytest
import yaml

from nightcrew.robotic.archives import SqliteTaskArchive, YamlTaskArchive
from nightcrew.robotic.archives._local import LocalTaskArchive
from nightcrew.robotic.runner import Script, TaskRunner
from nightcrew.robotic.scripts import CalibrationScript, ImagingScript
from nightcrew.robotic.tasks import Task, TaskProgress, TaskState, parse_request_group

from .runner_sim import PLEIADES, SimSetup, request_group, sim

__all__ = ["sim"]


def config(*filters: str, count: int = 3) -> dict[str, Any]:
    return {
        "type": "EXPOSE",
        "target": PLEIADES,
        "instrument_configs": [
            {"exposure_time": 1.0, "exposure_count": count, "optical_elements": {"filter": f}, "binning": 2}
            for f in filters
        ],
    }


BIAS = {"type": "BIAS", "instrument_configs": [{"exposure_time": 0, "exposure_count": 2, "binning": 2}]}


async def sqlite_archive(tmp_path: Path, data: dict[str, Any], sim: SimSetup) -> tuple[LocalTaskArchive, str]:
    archive = SqliteTaskArchive(tmp_path / "tasks.sqlite", clock=sim.obs.clock, poll_interval=0)
    await archive.open()
    (task,) = await archive.add_request_group(parse_request_group(data))
    return archive, task.id


async def yaml_archive(tmp_path: Path, data: dict[str, Any], sim: SimSetup) -> tuple[LocalTaskArchive, str]:
    path = tmp_path / "tasks.yaml"
    path.write_text(yaml.safe_dump([data]), encoding="utf-8")
    archive = YamlTaskArchive(path, clock=sim.obs.clock, poll_interval=0)
    await archive.open()
    return archive, "runner test/0"


ArchiveFactory = Callable[[Path, dict[str, Any], SimSetup], Any]


@pytest.fixture(params=[sqlite_archive, yaml_archive], ids=["sqlite", "yaml"])
def make_archive(request: pytest.FixtureRequest) -> ArchiveFactory:
    factory: ArchiveFactory = request.param
    return factory


class Attempt:
    """One run of a task as the mastermind makes it: started, progress recorded, ended in the archive."""

    def __init__(self, archive: LocalTaskArchive, runner: TaskRunner, task_id: str) -> None:
        self.archive, self.runner, self.task_id = archive, runner, task_id
        self.progress = TaskProgress()
        self.reached = asyncio.Event()
        self.stop_after = -1

    async def on_progress(self, progress: TaskProgress) -> None:
        self.progress = progress
        await self.archive.record_progress(self.task_id, progress)
        if progress.total_exposures == self.stop_after:
            self.reached.set()

    async def interrupted_after(self, exposures: int) -> Task:
        """Run, cancel the run once ``exposures`` frames are recorded, mark it FAILED."""
        self.stop_after = exposures
        task = await self.archive.mark_started(self.task_id)
        running = asyncio.create_task(self.runner.run_task(task, self.on_progress))
        await asyncio.wait_for(self.reached.wait(), 60)
        running.cancel()
        with pytest.raises(asyncio.CancelledError):
            await running
        return await self.archive.mark_failed(self.task_id, "interrupted by bad weather", self.progress)

    async def to_the_end(self) -> Task:
        task = await self.archive.mark_started(self.task_id)
        await self.runner.run_task(task, self.on_progress)
        return await self.archive.mark_finished(self.task_id, self.progress)


@pytest.fixture
async def archives() -> AsyncIterator[list[LocalTaskArchive]]:
    opened: list[LocalTaskArchive] = []
    yield opened
    for archive in opened:
        await archive.close()


async def test_a_retry_takes_only_the_missing_frames(
    sim: SimSetup, tmp_path: Path, make_archive: ArchiveFactory, archives: list[LocalTaskArchive]
) -> None:
    scripts: dict[str, Script | dict[str, Any]] = {"EXPOSE": ImagingScript(), "BIAS": CalibrationScript()}
    runner = await sim.runner(scripts)
    archive, task_id = await make_archive(tmp_path, request_group(BIAS, config("V", "R")), sim)
    archives.append(archive)

    # Bias frames and 2 V frames, then the weather turns.
    failed = await Attempt(archive, runner, task_id).interrupted_after(4)
    assert failed.state is TaskState.FAILED
    assert failed.status.progress.exposures_done == ((2,), (2, 0))
    first = len(sim.frames)
    assert first >= 4  # a frame aborted by the cancellation is not announced, nor counted

    finished = await Attempt(archive, runner, task_id).to_the_end()

    assert finished.state is TaskState.COMPLETED
    assert finished.status.progress.exposures_done == ((2,), (3, 3))
    headers = await sim.headers(first + 4)
    assert [(h["IMAGETYP"], h["FILTER"]) for h in headers[first:]] == [
        ("object", "V"),
        ("object", "R"),
        ("object", "R"),
        ("object", "R"),
    ]


async def test_a_finished_configuration_is_not_run_again(
    sim: SimSetup, tmp_path: Path, archives: list[LocalTaskArchive]
) -> None:
    runner = await sim.runner({"EXPOSE": ImagingScript()})
    data = request_group(config("V", count=2), config("R", count=2))
    archive, task_id = await sqlite_archive(tmp_path, data, sim)
    archives.append(archive)
    await Attempt(archive, runner, task_id).interrupted_after(3)
    first = len(sim.frames)

    finished = await Attempt(archive, runner, task_id).to_the_end()

    assert finished.status.progress.exposures_done == ((2,), (2,))
    headers = await sim.headers(first + 1)
    assert [h["FILTER"] for h in headers[first:]] == ["R"]  # no V frame again


def test_remaining_and_nothing_left_follow_the_recorded_progress() -> None:
    repeat = {
        "type": "REPEAT_EXPOSE",
        "target": PLEIADES,
        "repeat_duration": 10.0,
        "instrument_configs": [{"exposure_time": 3.0, "exposure_count": 1}],
    }
    script = {"type": "SCRIPT", "extra_params": {"script": "pointing", "duration": 60}}
    request = parse_request_group(request_group(config("V", "R"), repeat, script)).requests[0]
    progress = TaskProgress(exposures_done=((3, 1), (3,), ()))
    assert [progress.remaining(request, 0, i) for i in (0, 1)] == [0, 2]
    assert not progress.nothing_left(request, 0)
    assert progress.repeat_time_left(request, 1) == pytest.approx(1.0)
    assert not progress.nothing_left(request, 1)  # 1 s of the repeat is left
    assert TaskProgress(exposures_done=((3, 3), (4,), ())).nothing_left(request, 1)
    assert TaskProgress(exposures_done=((3, 3), (4,), ())).nothing_left(request, 0)
    assert not progress.nothing_left(request, 2)  # records nothing: always runs again
    assert TaskProgress().or_nothing(request) == TaskProgress.nothing_done(request)
