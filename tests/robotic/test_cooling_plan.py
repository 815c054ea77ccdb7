"""The cooling schedule's decisions: ramps, when to start cooling, holding, warming up at dawn."""

from __future__ import annotations

import pytest

from nightcrew.interfaces import CoolingStatus
from nightcrew.robotic.cooling import (
    CoolerCommand,
    CoolingPhase,
    CoolingPlan,
    cooler_settled,
    cooling_command,
    ramp_duration,
    ramp_step,
)

PLAN = CoolingPlan(setpoint=-10.0, ramp_rate=2.0, lead_time=600.0, warm_up_time_limit=1800.0)
DUSK = 100_000.0  # the Sun sets below the ready altitude
DAWN = 140_000.0  # ... and rises above the warm altitude


def command(
    now: float,
    *,
    last: CoolerCommand | None,
    last_time: float,
    temperature: float = 10.0,
    warming_since: float | None = None,
) -> CoolerCommand:
    # Before dusk the next crossings are tonight's dusk then dawn; in the night, dawn then tomorrow's dusk.
    ready_at, warm_at = (DUSK, DAWN) if now < DUSK or now >= DAWN else (DUSK + 86400.0, DAWN)
    if now >= DAWN:
        ready_at, warm_at = DUSK + 86400.0, DAWN + 86400.0
    return cooling_command(
        PLAN,
        now=now,
        ready_at=ready_at,
        warm_at=warm_at,
        temperature=temperature,
        warm_temperature=10.0,
        last=last,
        last_time=last_time,
        warming_since=warming_since,
    )


def test_ramps_move_at_most_the_rate_and_stop_at_the_target() -> None:
    assert ramp_duration(10.0, -10.0, 2.0) == pytest.approx(600.0)
    assert ramp_step(10.0, -10.0, 2.0, 60.0) == pytest.approx(8.0)
    assert ramp_step(-9.0, -10.0, 2.0, 60.0) == -10.0
    assert ramp_step(-10.0, 10.0, 2.0, 30.0) == pytest.approx(-9.0)
    assert ramp_step(5.0, 10.0, 2.0, -5.0) == 5.0  # time never runs back


def test_cooling_starts_a_ramp_and_a_lead_time_before_dusk() -> None:
    start = DUSK - 600.0 - 600.0  # lead time, then 20 °C at 2 °C/min
    assert command(start - 30.0, last=None, last_time=0.0) == CoolerCommand(CoolingPhase.OFF, False, -10.0)
    first = command(start, last=None, last_time=0.0)
    assert first == CoolerCommand(CoolingPhase.COOLING, True, 10.0)  # from the chip, not a jump
    last, t = first, start
    while last.phase is CoolingPhase.COOLING:
        last, t = command(t + 30.0, last=last, last_time=t), t + 30.0
        assert last.setpoint >= -10.0
    assert last == CoolerCommand(CoolingPhase.HOLDING, True, -10.0)
    assert t == pytest.approx(start + 600.0)  # the ramp rate held
    assert t <= DUSK - PLAN.lead_time
    # Held all night.
    assert command(DUSK + 3600.0, last=last, last_time=DUSK, temperature=-10.0) == last


def test_started_in_the_night_it_cools_at_once() -> None:
    assert command(DUSK + 7200.0, last=None, last_time=0.0).phase is CoolingPhase.COOLING


def test_dawn_warms_up_with_a_ramp_then_switches_off() -> None:
    holding = CoolerCommand(CoolingPhase.HOLDING, True, -10.0)
    warming = command(DAWN, last=holding, last_time=DAWN - 30.0, temperature=-10.0)
    assert warming == CoolerCommand(CoolingPhase.WARMING, True, -9.0)
    done = command(
        DAWN + 600.0,
        last=CoolerCommand(CoolingPhase.WARMING, True, 9.5),
        last_time=DAWN + 570.0,
        temperature=9.5,
        warming_since=DAWN,
    )
    assert done == CoolerCommand(CoolingPhase.OFF, False, -10.0)


def test_a_warm_up_that_does_not_end_is_cut_off_by_its_time_limit() -> None:
    stuck = CoolerCommand(CoolingPhase.WARMING, True, 10.0)  # at the target, the chip still cold
    still = command(DAWN + 1000.0, last=stuck, last_time=DAWN + 970.0, temperature=-5.0, warming_since=DAWN)
    assert still.phase is CoolingPhase.WARMING
    off = command(DAWN + 1800.0, last=stuck, last_time=DAWN + 1770.0, temperature=-5.0, warming_since=DAWN)
    assert off == CoolerCommand(CoolingPhase.OFF, False, -10.0)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"setpoint": -150.0}, "setpoint must be within -100..50"),
        ({"setpoint": -10.0, "ramp_rate": 0.0}, "ramp_rate must be > 0"),
        ({"setpoint": -10.0, "warm_up_time_limit": 0.0}, "warm_up_time_limit must be > 0"),
        ({"setpoint": -10.0, "ready_sun_altitude": 95.0}, "ready_sun_altitude must be within"),
    ],
)
def test_a_bad_plan_is_refused_naming_the_value(options: dict[str, float], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        CoolingPlan(**options)


def test_a_frame_waits_only_for_a_cooler_that_is_on_and_off_its_set_point() -> None:
    assert not cooler_settled(CoolingStatus(True, -10.0, 60.0, temperature=-9.2), 0.5)
    assert cooler_settled(CoolingStatus(True, -10.0, 60.0, temperature=-9.6), 0.5)
    assert cooler_settled(CoolingStatus(False, -10.0, 0.0, temperature=15.0), 0.5)  # not cooling
    assert cooler_settled(CoolingStatus(True, -10.0, 60.0), 0.5)  # says no temperature
