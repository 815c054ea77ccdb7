"""The simulated cooler: a first-order chip against ambient air, exact for any step size."""

from __future__ import annotations

import pytest

from nightcrew.sim.thermal import ChipTemperature, CoolerModel, advance_chip

MODEL = CoolerModel(ambient=10.0, max_delta=30.0, time_constant=60.0)


def test_the_chip_settles_at_a_reachable_set_point_and_one_step_equals_many() -> None:
    start = ChipTemperature(0.0, 10.0)
    one = advance_chip(MODEL, start, 600.0, enabled=True, setpoint=-10.0)
    many = start
    for t in range(60, 601, 60):
        many = advance_chip(MODEL, many, float(t), enabled=True, setpoint=-10.0)
    assert one.temperature == pytest.approx(many.temperature)
    assert one.temperature == pytest.approx(-10.0, abs=1e-3)
    assert MODEL.power(True, -10.0) == pytest.approx(100.0 * 20.0 / 30.0)


def test_an_unreachable_set_point_shows_a_warm_chip_at_full_power() -> None:
    chip = advance_chip(MODEL, ChipTemperature(0.0, 10.0), 3600.0, enabled=True, setpoint=-40.0)
    assert chip.temperature == pytest.approx(MODEL.coldest, abs=1e-3)
    assert MODEL.coldest == -20.0
    assert MODEL.power(True, -40.0) == 100.0


def test_switched_off_the_chip_warms_to_ambient_without_power() -> None:
    chip = advance_chip(MODEL, ChipTemperature(0.0, -10.0), 60.0, enabled=False, setpoint=-10.0)
    assert chip.temperature == pytest.approx(10.0 - 20.0 / 2.718281828, abs=1e-3)
    assert MODEL.power(False, -10.0) == 0.0


def test_bad_physics_is_refused() -> None:
    with pytest.raises(ValueError, match="max_delta must be > 0"):
        CoolerModel(max_delta=0.0)
