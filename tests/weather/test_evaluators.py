"""The pure weather evaluation: evaluators, hysteresis, staleness, Current/Average and the gate."""

from __future__ import annotations

import pytest

from nightcrew.errors import ConfigError, InvalidArgumentError
from nightcrew.weather import (
    Boolean,
    GoodWeatherGate,
    Reading,
    Schmitt,
    SensorCheck,
    Switch,
    Valid,
    Verdict,
    WeatherChange,
    average_reading,
    json_pointer,
    last_csv_row,
    latest_reading,
    parse_number,
    parse_time,
)

NOW = 1_700_000_000.0


def at(value: float | None, age: float = 0.0) -> Reading:
    return Reading(NOW - age, value)


def test_boolean_rain_sensor() -> None:
    dry_is_good = Boolean(good_when=False)
    assert dry_is_good.evaluate(at(0.0), NOW).good
    assert dry_is_good.evaluate(at(1.0), NOW) == Verdict(False, "is true")
    assert Boolean(good_when=True).evaluate(at(1.0), NOW).good


@pytest.mark.parametrize("evaluator", [Boolean(), Switch(bad_above=1), Schmitt(bad_above=2, good_below=1)])
def test_no_reading_or_no_value_is_bad(evaluator: Boolean | Switch | Schmitt) -> None:
    assert evaluator.evaluate(None, NOW) == Verdict(False, "no value")
    assert evaluator.evaluate(at(None), NOW) == Verdict(False, "no value")
    assert not evaluator.evaluate(None, NOW, previous=Verdict(True)).good


def test_switch_one_threshold_each_side() -> None:
    wind = Switch(bad_above=50.0)
    assert wind.evaluate(at(49.9), NOW).good
    assert wind.evaluate(at(50.0), NOW) == Verdict(False, "50 >= 50")
    sun = Switch(bad_above=-6.0)
    assert not sun.evaluate(at(-3.0), NOW).good
    frost = Switch(bad_below=-20.0)
    assert frost.evaluate(at(-19.0), NOW).good and not frost.evaluate(at(-25.0), NOW).good


def test_schmitt_hysteresis_upper() -> None:
    humidity = Schmitt(bad_above=90.0, good_below=85.0)
    verdicts: list[bool] = []
    previous: Verdict | None = None
    for value in [80, 87, 91, 88, 86, 84.9, 87, 89.9, 90]:
        previous = humidity.evaluate(at(value), NOW, previous)
        verdicts.append(previous.good)
    # 87 at the start: between thresholds with nothing before → bad (fail safe).
    assert verdicts == [True, True, False, False, False, True, True, True, False]


def test_schmitt_starts_bad_between_thresholds() -> None:
    humidity = Schmitt(bad_above=90.0, good_below=85.0)
    assert humidity.evaluate(at(87.0), NOW) == Verdict(False, "87 not yet below 85")


def test_schmitt_hysteresis_lower() -> None:
    sky = Schmitt(bad_below=-40.0, good_above=-35.0)  # e.g. a "clear sky" margin the other way round
    first = sky.evaluate(at(-41.0), NOW)
    assert not first.good
    assert not sky.evaluate(at(-37.0), NOW, first).good
    assert sky.evaluate(at(-34.0), NOW, first).good
    assert sky.evaluate(at(-37.0), NOW, Verdict(True)).good


@pytest.mark.parametrize(
    ("kwargs", "key", "message"),
    [
        ({"bad_above": 90}, "good_below", "give good_below"),
        ({"bad_above": 90, "good_below": 95}, "good_below", r"must be <= bad_above \(90\)"),
        ({"bad_below": 0, "good_above": -5}, "good_above", r"must be >= bad_below \(0\)"),
        ({"bad_above": 1, "bad_below": 0}, "bad_above", "exactly one"),
        ({}, "bad_above", "exactly one"),
    ],
)
def test_schmitt_config_errors_name_the_key(kwargs: dict[str, float], key: str, message: str) -> None:
    with pytest.raises(ConfigError, match=message) as info:
        Schmitt(**kwargs)
    assert info.value.key == key


def test_valid_turns_stale_after_five_minutes() -> None:
    valid = Valid()
    assert valid.evaluate(at(1.0, age=299.0), NOW).good
    assert valid.evaluate(at(1.0, age=301.0), NOW) == Verdict(False, "stale (301 s old)")
    assert not Valid(max_age=10).evaluate(at(1.0, age=11.0), NOW).good
    with pytest.raises(ConfigError, match="must be > 0") as info:
        Valid(max_age=0)
    assert info.value.key == "max_age"


def test_a_check_is_a_valid_check_by_default() -> None:
    check = SensorCheck("roof", "rain", [Boolean()])
    assert isinstance(check.evaluators[0], Valid)
    fresh = check.evaluate(at(0.0), NOW, None)
    assert fresh.good and check.name == "roof.rain"
    stale = check.evaluate(at(0.0, age=600.0), NOW, fresh)
    assert not stale.good and stale.reason == "stale (600 s old)"
    own = SensorCheck("roof", "rain", [Valid(max_age=900), Boolean()])
    assert len(own.evaluators) == 2 and own.evaluate(at(0.0, age=600.0), NOW, None).good


def test_a_check_keeps_hysteresis_per_evaluator() -> None:
    check = SensorCheck("a", "humidity", [Schmitt(bad_above=90, good_below=85)])
    result = check.evaluate(at(80.0), NOW, None)
    result = check.evaluate(at(88.0), NOW, result)
    assert result.good  # still good between the thresholds
    result = check.evaluate(at(95.0), NOW, result)
    result = check.evaluate(at(88.0), NOW, result)
    assert not result.good and result.reason == "88 not yet below 85"


def test_current_is_the_newest_reading_with_a_value() -> None:
    readings = [at(1.0, age=30), at(2.0, age=10), at(None, age=0), None]
    assert latest_reading(readings) == at(2.0, age=10)
    assert latest_reading([None, at(None)]) is None
    assert latest_reading([]) is None


def test_average_leaves_out_stale_and_empty_readings() -> None:
    readings = [at(10.0, age=30), at(20.0, age=60), at(100.0, age=400), at(None), None]
    mean = average_reading(readings, NOW, max_age=300)
    assert mean == Reading(NOW - 60, 15.0)  # as old as its oldest input
    assert average_reading([at(1.0, age=400)], NOW, max_age=300) is None
    assert average_reading([], NOW, max_age=300) is None


def declared_good(gate: GoodWeatherGate) -> bool:
    return gate.is_good  # a call, so mypy does not narrow the property between asserts


def eta_of(gate: GoodWeatherGate) -> float | None:
    return gate.eta


def test_gate_declares_bad_at_once_and_good_after_the_minimum_time() -> None:
    gate = GoodWeatherGate(min_good_time=600)
    assert gate.update(True, 0) is None and eta_of(gate) == 600  # starting: nothing declared yet
    assert not declared_good(gate)
    assert gate.update(True, 599) is None
    assert gate.update(True, 600) is WeatherChange.GOOD and declared_good(gate)
    assert gate.update(True, 700) is None
    assert gate.update(False, 710) is WeatherChange.BAD
    assert eta_of(gate) is None
    assert gate.update(False, 720) is None
    assert gate.update(True, 730) is None
    assert gate.update(False, 1000) is None  # a short dry spell resets the timer
    assert gate.update(True, 1010) is None
    assert gate.update(True, 1609) is None
    assert gate.update(True, 1610) is WeatherChange.GOOD


def test_gate_announces_bad_first() -> None:
    gate = GoodWeatherGate(min_good_time=0)
    assert gate.update(False, 0) is WeatherChange.BAD
    assert gate.update(True, 1) is WeatherChange.GOOD
    with pytest.raises(ValueError, match="min_good_time must be >= 0"):
        GoodWeatherGate(-1)


def test_json_pointer() -> None:
    document = {"current": {"temp": 4.5, "a/b": 1, "list": [{"v": 3}]}}
    assert json_pointer(document, "/current/temp") == 4.5
    assert json_pointer(document, "/current/a~1b") == 1
    assert json_pointer(document, "/current/list/0/v") == 3
    with pytest.raises(InvalidArgumentError, match="nothing at 'nope'"):
        json_pointer(document, "/current/nope")
    with pytest.raises(InvalidArgumentError, match="must start with '/'"):
        json_pointer(document, "current")


def test_parsing_values_and_times() -> None:
    assert [parse_number(v) for v in (3, "4.5", True, "false", None, "")] == [3.0, 4.5, 1.0, 0.0, None, None]
    with pytest.raises(InvalidArgumentError, match="not a number: 'wet'"):
        parse_number("wet")
    assert parse_time("2023-11-14T22:13:20") == NOW == parse_time("2023-11-14T22:13:20+00:00")
    assert parse_time(NOW) == NOW == parse_time(str(NOW))


def test_last_csv_row() -> None:
    data = b"time,T,rain\n2023-11-14T22:00:00,5.0,0\n2023-11-14T22:13:20,4.5,1\n\n"
    assert last_csv_row(data) == {"time": "2023-11-14T22:13:20", "T": "4.5", "rain": "1"}
    with pytest.raises(InvalidArgumentError, match="no data row"):
        last_csv_row(b"time,T\n")
