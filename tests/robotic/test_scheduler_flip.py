"""The scheduler counts a meridian flip's time in blocks whose target crosses the meridian."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

import pytest

from nightcrew.errors import InvalidArgumentError
from nightcrew.robotic.scheduler import Night, SchedulableBlock, Scheduler, Target
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
START = datetime(2024, 1, 15, 17, 0, tzinfo=UTC)
NIGHT = Night(START, START + timedelta(hours=13), SITE)
ORION = Target(ra=83.8, dec=-5.4)  # crosses the meridian at about 22:40 UTC, well up
NOON_TRANSIT = Target(ra=290.0, dec=80.0)  # circumpolar, crosses the meridian by day only


def test_a_block_whose_target_crosses_the_meridian_is_padded_by_the_flip() -> None:
    blocks = [
        SchedulableBlock(id="orion", priority=1.0, duration_s=1800.0, target=ORION),
        SchedulableBlock(id="polar", priority=1.0, duration_s=1800.0, target=NOON_TRANSIT),
    ]
    scheduler = Scheduler(step_s=300.0, slew_overhead_s=0.0, meridian_flip_s=600.0, time_limit_s=2.0)
    problem = scheduler.problem(blocks, NIGHT)
    assert list(problem.flip_s) == [600.0, 0.0]
    assert list(problem.lengths) == [8, 6]  # (1800 + 600) / 300 and 1800 / 300 slices
    slots = {slot.task_id: slot for slot in scheduler.schedule(blocks, NIGHT).slots}
    assert (slots["orion"].end - slots["orion"].start).total_seconds() == pytest.approx(2400.0)
    assert (slots["polar"].end - slots["polar"].start).total_seconds() == pytest.approx(1800.0)
    # Without flips (the default: not a German-equatorial mount) nothing is padded.
    assert list(Scheduler(slew_overhead_s=0.0).problem(blocks, NIGHT).flip_s) == [0.0, 0.0]


def test_a_negative_flip_time_is_refused() -> None:
    with pytest.raises(InvalidArgumentError, match="meridian_flip_s must be >= 0, got -1"):
        Scheduler(meridian_flip_s=-1.0)
