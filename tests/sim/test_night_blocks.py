"""Blocks for the simulated night's calibration tasks: near the pole, weighted, flats twilight-long."""

from __future__ import annotations

from nightcrew.modules.sim.night_blocks import CALIBRATION_WEIGHT, SKY_FLAT_SECONDS, calibration_block
from nightcrew.modules.sim.whole_night_plan import one_window_each
from nightcrew.robotic.samples import load_samples
from nightcrew.robotic.tasks import RequestGroup, Task
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
    with_site = calibration_block(task_of(dusk), SITE)
    # The Sun goes from -3 to -12 degrees in about 58 minutes on that evening: 3/4 of that.
    assert 2400.0 < with_site.duration_s < 2900.0
    assert calibration_block(task_of(dusk)).duration_s == SKY_FLAT_SECONDS
