"""Weather scenarios: interpolation, carried-over fields, validation, seeded random nights."""

from __future__ import annotations

import pytest

from nightcrew.sim.weather import WeatherScenario, WeatherState, random_scenario


def test_scripted_scenario_interpolates_smooth_values_and_steps_rain() -> None:
    scenario = WeatherScenario.from_config(
        [
            {"at": 0, "temperature": 10, "clouds": 0.0},
            {"at": 100, "temperature": 0, "clouds": 1.0, "rain": True},
        ]
    )
    middle = scenario.state_at(50.0)
    assert (middle.temperature, middle.clouds, middle.rain) == (5.0, 0.5, False)
    assert scenario.state_at(100.0).rain is True and scenario.state_at(1e6).temperature == 0.0
    assert scenario.state_at(-5.0).temperature == 10.0 and scenario.duration == 100.0


def test_fields_not_named_carry_over() -> None:
    scenario = WeatherScenario.from_config([{"at": 0, "humidity": 80}, {"at": 60, "wind_speed": 50}])
    assert scenario.state_at(60.0).humidity == 80.0


@pytest.mark.parametrize(
    ("entries", "message"),
    [
        ([], "needs at least one state"),
        ([{"at": 5}], "must start at 0 and increase"),
        ([{"at": 0}, {"at": 0}], "must start at 0 and increase"),
        ([{"temperature": 3}], "entry 0: missing 'at'"),
        ([{"at": 0, "clouds": 2}], "entry 0: clouds must be within 0..1, got 2"),
    ],
)
def test_bad_scenarios_are_refused_naming_the_problem(entries: list[dict[str, float]], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        WeatherScenario.from_config(entries)


def test_sensors_derive_dew_point_and_sky_temperature() -> None:
    sensors = WeatherState(temperature=10.0, humidity=100.0, clouds=0.5, rain=True).sensors()
    assert sensors["dew_point"] == pytest.approx(10.0, abs=0.01)
    assert sensors["sky_temperature"] == -5.0 and sensors["rain"] == 1.0


def test_random_scenarios_repeat_with_the_seed_and_stay_plausible() -> None:
    a, b, c = random_scenario(3), random_scenario(3), random_scenario(4)
    times = [0.0, 1234.0, 20000.0, 43200.0]
    assert [a.state_at(t) for t in times] == [b.state_at(t) for t in times]
    assert [a.state_at(t) for t in times] != [c.state_at(t) for t in times]
    for t in range(0, 43200, 600):
        state = a.state_at(float(t))
        assert 0 <= state.clouds <= 1 and 0 <= state.humidity <= 100 and state.wind_speed >= 0
