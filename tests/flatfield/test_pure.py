"""The pure flat-field parts: T_min/T_max decisions, sky factor, functions, pointing, priorities."""

from __future__ import annotations

import math
from datetime import UTC, datetime, timedelta

import pytest

from nightcrew.errors import ConfigError
from nightcrew.flatfield import (
    Decision,
    ExposureTimeFunctions,
    FlatExposureControl,
    FlatLimits,
    Twilight,
    antisolar_position,
    dither_offset,
    last_taken_from_plain,
    prioritised,
    tasks_from_config,
    twilight_from_altitudes,
)

LIMITS = FlatLimits(target=30000, bias=1000, tolerance=0.1, saturation=60000, min_exposure=1, max_exposure=30)


@pytest.mark.parametrize(
    ("twilight", "seconds", "decision"),
    [
        (Twilight.DUSK, 0.5, Decision.WAIT),  # too bright, darkening: wait
        (Twilight.DUSK, 10.0, Decision.EXPOSE),
        (Twilight.DUSK, 40.0, Decision.STOP),  # too dark and getting darker
        (Twilight.DAWN, 0.5, Decision.STOP),  # too bright and getting brighter
        (Twilight.DAWN, 10.0, Decision.EXPOSE),
        (Twilight.DAWN, 40.0, Decision.WAIT),  # too dark, brightening: wait
        (Twilight.DUSK, 1.0, Decision.EXPOSE),  # limits included
        (Twilight.DAWN, 30.0, Decision.EXPOSE),
    ],
)
def test_t_min_t_max_logic(twilight: Twilight, seconds: float, decision: Decision) -> None:
    assert FlatExposureControl(LIMITS, twilight).decide(seconds) is decision


def test_twilight_from_the_suns_motion() -> None:
    assert twilight_from_altitudes(-5.0, -5.1) is Twilight.DUSK
    assert twilight_from_altitudes(-5.0, -4.9) is Twilight.DAWN


def test_the_sky_factor_scales_the_next_exposure_to_the_target() -> None:
    control = FlatExposureControl(LIMITS, Twilight.DUSK)
    # The function said 2 s; the sky gave half the wanted signal: it is half as bright as modelled.
    assert not control.learn(exposure_time=2.0, modelled=2.0, level=1000 + 14500)
    assert control.sky_factor == pytest.approx(0.5)
    assert control.exposure_time(3.0) == pytest.approx(6.0)
    # A frame on target counts; one 15 % off does not (tolerance 10 %).
    assert control.learn(6.0, 3.0, 30000.0)
    assert not control.learn(6.0, 3.0, 1000 + 29000 * 1.15)


def test_saturated_and_empty_frames_shorten_or_lengthen_a_lot() -> None:
    control = FlatExposureControl(LIMITS, Twilight.DUSK)
    assert not control.learn(1.0, 1.0, 65000.0)
    assert control.sky_factor > 2.2 * 3  # at least this bright, and then some
    control = FlatExposureControl(LIMITS, Twilight.DAWN)
    assert not control.learn(1.0, 1.0, 900.0)
    assert control.sky_factor == pytest.approx(0.1)


def test_exposure_time_functions_per_filter_and_binning() -> None:
    functions = ExposureTimeFunctions({"V": {"1x1": "exp(-1.22*(h + 4.07))", "2x2": "exp(-1.22*(h + 5.2))"}})
    function = functions.function("V", (1, 1))
    assert functions.evaluate(function, -4.07) == pytest.approx(1.0)
    assert functions.evaluate(function, -5.07) == pytest.approx(math.exp(1.22))
    assert functions.combinations() == [("V", "1x1"), ("V", "2x2")]
    with pytest.raises(
        ValueError, match="no exposure-time function for filter R, binning 1x1; have V/1x1, V/2x2"
    ):
        functions.function("R", (1, 1))
    assert ExposureTimeFunctions({"none": {"1x1": "2"}}).function(None, (1, 1)).text == "2"


@pytest.mark.parametrize(
    ("functions", "message"),
    [
        ({}, r"key 'functions': needs at least one filter"),
        ({"V": {"two": "h"}}, r"key 'functions.V.two': expected a binning like '2x2'"),
        ({"V": {"1x1": "exp(-k*(h+4))"}}, r"key 'functions.V.1x1': a function may only use 'h'.*not k"),
        ({"V": {"1x1": "os.system('x')"}}, r"key 'functions.V.1x1': attribute access"),
        ({"V": "exp(h)"}, r"key 'functions.V': expected a mapping of binning"),
    ],
)
def test_bad_functions_name_the_key(functions: dict[str, dict[str, str]], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        ExposureTimeFunctions(functions)


def test_flats_point_opposite_the_sun_at_80_degrees_and_dither() -> None:
    assert antisolar_position(250.0) == (80.0, 70.0)
    positions = [antisolar_position(250.0, index=i, dither_arcsec=120.0) for i in range(20)]
    assert len(set(positions)) == 20
    for index in range(1, 20):
        dalt, dsky = dither_offset(index, 120.0)
        assert math.hypot(dalt, dsky) == pytest.approx(120.0 / 3600.0 * math.sqrt(index))
    # Azimuth offsets are stretched by 1/cos(alt), so stars move by the full dither on the sky.
    alt, az = antisolar_position(0.0, index=1, dither_arcsec=3600.0)
    _, dsky = dither_offset(1, 3600.0)
    assert (az - 180.0) * math.cos(math.radians(alt)) == pytest.approx(dsky, rel=1e-6)


def test_schedule_priorities_from_time_since_last_taken() -> None:
    tasks = tasks_from_config(
        [
            {"filter": "V", "binning": "2x2", "count": 5},
            {"filter": "R", "binning": "2x2", "count": 5, "weight": 3},
            {"filter": "B", "binning": "1x1", "count": 5},
            {"filter": "I", "binning": "1x1"},
        ]
    )
    now = datetime(2024, 1, 15, 16, tzinfo=UTC)
    last = {
        "V 2x2": now - timedelta(days=1),
        "R 2x2": now - timedelta(hours=12),
        "B 1x1": now - timedelta(days=3),
    }
    # I never taken: first. Then weight x hours: B 72, R 3*12 = 36, V 24.
    assert [t.key for t in prioritised(tasks, last, now)] == ["I 1x1", "B 1x1", "R 2x2", "V 2x2"]
    assert tasks[3].count == 10


@pytest.mark.parametrize(
    ("entries", "message"),
    [
        ([], r"key 'flats': needs at least one"),
        ([{"filter": "V", "binning": "2"}], r"key 'flats\[0\].binning'"),
        ([{"filter": "V", "count": 0}], r"key 'flats\[0\].count': must be a whole number >= 1"),
        ([{"filter": "V", "colour": "red"}], r"key 'flats\[0\]': unknown keys \['colour'\]"),
        ([{"filter": "V"}, {"filter": "V", "binning": "1x1"}], r"key 'flats\[1\]': V 1x1 is listed twice"),
    ],
)
def test_bad_schedule_names_the_entry(entries: list[dict[str, object]], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        tasks_from_config(entries)


def test_persisted_schedule_state_is_read_forgivingly() -> None:
    state, problems = last_taken_from_plain(
        {"V 2x2": "2024-01-15T16:00:00+00:00", "R 2x2": "soon", "B 1x1": "2024-01-15"}
    )
    assert list(state) == ["V 2x2"]
    assert len(problems) == 2
