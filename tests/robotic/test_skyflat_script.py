"""SkyFlatScript on the simulated twilight: instrument configs in the order the twilight planner gives."""

from __future__ import annotations

import pytest

from nightcrew.modules import Module
from nightcrew.robotic.runner import ScriptError, TaskRunner
from nightcrew.robotic.scripts import SkyFlatScript
from nightcrew.robotic.tasks import TaskProgress, TaskStatus
from tests.flatfield.sim import FUNCTIONS, TwilightObservatory, start_flat_observatory
from tests.flatfield.test_flatfield_sim import dusk, frames

from .runner_sim import ProgressLog, make_task

__all__ = ["dusk"]


def sky_flats(*filters: str, count: int = 3) -> dict[str, object]:
    return {
        "type": "SKY_FLAT",
        "constraints": {"min_sun_altitude": -12, "max_sun_altitude": -3},
        "instrument_configs": [
            {"exposure_time": 3, "exposure_count": count, "optical_elements": {"filter": f}, "binning": 2}
            for f in filters
        ],
    }


async def runner_on(obs: TwilightObservatory, script: SkyFlatScript) -> TaskRunner:
    host = await obs.start(Module, "robotic")
    runner = host.add_child(TaskRunner(scripts={"SKY_FLAT": script}))
    await runner.open()
    return runner


async def test_at_dusk_the_planned_order_takes_the_slow_filter_first(dusk: TwilightObservatory) -> None:
    await start_flat_observatory(dusk)
    runner = await runner_on(dusk, SkyFlatScript(functions=FUNCTIONS, max_exposure=30.0, overhead=5.0))
    task = make_task(sky_flats("V", "B"))
    progress = ProgressLog()
    await runner.run_task(task, progress)

    filters = [header["FILTER"] for header, _ in frames(dusk.directory)]
    assert filters[0] == "B" and filters.index("V") > filters.index("B")
    assert progress.last.exposures_done == ((3, 3),)  # counted against the task's own order


async def test_a_retry_takes_only_the_missing_flats(dusk: TwilightObservatory) -> None:
    await start_flat_observatory(dusk)
    runner = await runner_on(dusk, SkyFlatScript())
    task = make_task(sky_flats("V", "R"))
    done_before = TaskProgress(exposures_done=((3, 1),))
    task = task.with_status(TaskStatus(progress=done_before))
    progress = ProgressLog()
    await runner.run_task(task, progress)

    flats = [header["FILTER"] for header, _ in frames(dusk.directory)]
    assert set(flats) == {"R"}  # no V flat again
    assert progress.last.exposures_done == ((3, 3),)


async def test_a_twilight_too_short_for_all_flats_fails_the_task_with_what_is_missing(
    dusk: TwilightObservatory,
) -> None:
    # A T_max of 2 s ends the flats about 7 minutes after they start: far fewer than 100.
    await start_flat_observatory(dusk, max_exposure=2.0)
    runner = await runner_on(dusk, SkyFlatScript())
    progress = ProgressLog()
    with pytest.raises(
        ScriptError, match=r"sky flats incomplete: \d+ of 100 missing \(twilight over\?\)"
    ) as failed:
        await runner.run_task(make_task(sky_flats("V", count=100)), progress)
    (done,) = progress.last.exposures_done[0]  # kept for a retry
    assert 0 < done < 100 and failed.value.message.startswith(f"sky flats incomplete: {100 - done} of 100")
    assert len(frames(dusk.directory)) >= done  # (plus the flat-fielder's test exposures)
