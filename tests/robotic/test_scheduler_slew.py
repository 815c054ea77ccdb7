"""The slew model, and plans that pay every transition exactly."""

from __future__ import annotations

import itertools
from datetime import UTC, datetime, timedelta

import numpy as np
import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.scheduler import Night, Scheduler
from nightcrew.robotic.scheduler.sequence import pointing_of
from nightcrew.robotic.scheduler.slew import AxisMotion, Pointing, SlewModel
from nightcrew.robotic.scheduler.synthetic import synthetic_blocks
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
START = datetime(2024, 1, 15, 17, 0, tzinfo=UTC)
NIGHT = Night(START, START + timedelta(hours=13), SITE)
#: A slow amateur mount with a dome (the benchmark's too).
MOUNT = SlewModel(
    AxisMotion(2.0, 0.5), AxisMotion(1.5, 0.5), settle_s=5.0, dome=AxisMotion(3.0), filter_change_s=20.0
)


def test_an_axis_accelerates_then_cruises() -> None:
    axis = AxisMotion(rate=2.0, acceleration=0.5)  # 4 s and 4° to reach 2°/s, as many to stop
    assert float(axis.seconds(8.0)) == pytest.approx(8.0)  # all ramps: 2 * sqrt(8 / 0.5)
    assert float(axis.seconds(2.0)) == pytest.approx(4.0)  # a short move: 2 * sqrt(2 / 0.5)
    assert float(axis.seconds(108.0)) == pytest.approx(108.0 / 2.0 + 4.0)
    assert float(AxisMotion(rate=4.0).seconds(100.0)) == 25.0


def test_the_slowest_axis_or_the_dome_then_settling_and_a_filter_change() -> None:
    t = START.timestamp()
    same = MOUNT.transition_s(SITE, Pointing(10.0, 20.0, "V", "R"), Pointing(10.0, 20.0, "R", "B"), t)
    assert same == 0.0  # no move and the filter it already has
    dec_only = MOUNT.transition_s(SITE, Pointing(10.0, 20.0, "", "R"), Pointing(10.0, 80.0, "V"), t)
    assert dec_only >= 60.0 / 1.5 + 3.0 + 5.0 + 20.0 - 1e-6  # Dec axis (or the dome), settling, filter
    no_dome = SlewModel(AxisMotion(2.0, 0.5), AxisMotion(1.5, 0.5), settle_s=5.0)
    assert float(no_dome.slew_s(SITE, (10.0, 20.0), (10.0, 80.0), t)) == pytest.approx(60.0 / 1.5 + 3.0 + 5.0)
    # Pairs at once: a column of starts and a row of ends.
    grid = no_dome.slew_s(
        SITE, (np.array([[0.0], [90.0]]), np.array([[0.0], [0.0]])), (np.array([[0.0, 90.0]]), 0.0), t
    )
    assert grid.shape == (2, 2) and grid[0, 0] == 0.0 and grid[0, 1] == pytest.approx(90.0 / 2.0 + 4.0 + 5.0)


def test_a_mounts_configuration_gives_the_model() -> None:
    config = {"axis_rates": [2.0, 1.5], "acceleration": 0.5, "settle_time": 5.0, "dome_rate": 3.0}
    assert SlewModel.from_config({**config, "filter_change_s": 20.0}) == MOUNT
    assert SlewModel.from_config({"slew_rate": 4.0, "settle_time": 3.0}).axis2 == AxisMotion(4.0)


def test_a_bad_slew_configuration_is_refused_with_its_key() -> None:
    with pytest.raises(InvalidArgumentError, match="unknown keys slew_rat"):
        SlewModel.from_config({"slew_rat": 4.0})
    with pytest.raises(InvalidArgumentError, match="axis rate must be > 0"):
        SlewModel.from_config({"axis_rates": [4.0, 0.0]})
    with pytest.raises(InvalidArgumentError, match="give slew_rate or axis_rates"):
        SlewModel.from_config({"settle_time": 3.0})


def test_a_plan_pays_every_transition_keeps_a_valid_bound_and_beats_the_flat_pad() -> None:
    blocks = synthetic_blocks(NIGHT, 40, seed=4, min_duration_s=300.0, max_duration_s=1200.0)
    scheduler = Scheduler(step_s=300.0, slew=MOUNT)
    schedule = scheduler.schedule(blocks, NIGHT)
    by_id = {b.id: b for b in blocks}
    assert len(schedule.slots) > 15
    assert schedule.bound is not None and schedule.objective <= schedule.bound + 1e-9
    longest = 0.0
    for before, after in itertools.pairwise(schedule.slots):
        b, a = by_id[before.task_id], by_id[after.task_id]
        assert before.end <= after.start
        needed = MOUNT.transition_s(SITE, pointing_of(b), pointing_of(a), after.start.timestamp())
        longest = max(longest, needed)
        held = (after.end - after.start).total_seconds()
        assert held >= needed + a.setup_s + a.duration_s - 1e-6
    assert longest > 30.0  # real slews, not a flat pad
    flat = Scheduler(step_s=300.0, slew_overhead_s=100.0).schedule(blocks, NIGHT)
    assert schedule.objective >= flat.objective


def test_the_documented_slew_section_gives_a_model() -> None:
    import re
    from pathlib import Path

    import yaml

    text = (Path(__file__).parents[2] / "docs" / "scheduler.md").read_text(encoding="utf-8")
    (block,) = re.findall(r"```yaml\n(slew:.*?)```", text, flags=re.DOTALL)
    model = SlewModel.from_config(yaml.safe_load(block)["slew"])
    assert model.dome == AxisMotion(4.0) and model.axis1 == AxisMotion(3.0, 1.0) and model.settle_s == 5.0
