"""Blocks for the simulated night's calibration tasks: near the pole, weighted, flats twilight-long."""

from __future__ import annotations

from nightcrew.night.blocks import CALIBRATION_WEIGHT, SKY_FLAT_SECONDS, calibration_block
from nightcrew.night.plan import one_window_each
from nightcrew.robotic.samples import load_samples
from nightcrew.robotic.tasks import RequestGroup, Task, TaskProgress, TaskState, TaskStatus
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0)


def task_of(group: RequestGroup, index: int = 0) -> Task:
    return Task(
        id="1", group_id="1", name=group.name, proposal=group.proposal, priority=group.priority,
        request=group.requests[index],
    )  # fmt: skip


def test_bias_and_darks_go_near_the_pole_with_a_weighted_priority() -> None:
    group = load_samples()["bias-and-darks"]
    block = calibration_block(task_of(group))
    assert block.target.dec == 89.0 and block.priority == group.priority * CALIBRATION_WEIGHT
    assert block.constraints.max_sun_altitude == 90


def test_dusk_flats_take_most_of_the_twilight() -> None:
    dusk, _ = one_window_each(load_samples()["twilight-sky-flats"])
    # The sample's flats need the Sun between -3 and -9 degrees: about 37 minutes that evening, of
    # which 3/4 is less than the floor.
    assert calibration_block(task_of(dusk), SITE).duration_s == SKY_FLAT_SECONDS
    assert calibration_block(task_of(dusk)).duration_s == SKY_FLAT_SECONDS
    # Down to -12 degrees the Sun takes about 58 minutes: 3/4 of that.
    request = dusk.requests[0]
    configuration = request.configurations[0]
    deeper = configuration.model_copy(
        update={"constraints": configuration.constraints.model_copy(update={"min_sun_altitude": -12.0})}
    )
    longer = dusk.model_copy(update={"requests": (request.model_copy(update={"configurations": (deeper,)}),)})
    assert 2400.0 < calibration_block(task_of(longer), SITE).duration_s < 2900.0


def test_retried_darks_are_planned_for_the_frames_they_lack() -> None:
    darks = task_of(load_samples()["bias-and-darks"], 1)  # 5 x 60 s and 3 x 120 s
    # Default overheads: 15 s to set up, 2 s read-out + 1 s per frame; no filters to change.
    assert calibration_block(darks).duration_s == 15 + 5 * 63 + 3 * 123
    status = TaskStatus(
        state=TaskState.FAILED, reason="interrupted", progress=TaskProgress(exposures_done=((5, 1),))
    )
    assert calibration_block(darks.with_status(status)).duration_s == 15 + 2 * 123
