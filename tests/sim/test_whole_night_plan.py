"""The whole night's plan: its span, weather scenarios, sample tasks moved and split."""

from __future__ import annotations

from datetime import UTC, date, datetime

import pytest

from nightcrew.astro import sun_altitude
from nightcrew.night.plan import (
    night_span,
    one_window_each,
    shifted_group,
    survey_groups,
    weather_scenario,
)
from nightcrew.robotic.samples import load_samples
from nightcrew.sim.weather import WeatherScenario
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0)


def test_the_night_spans_the_twilights() -> None:
    start, end = night_span(date(2026, 11, 10), SITE)
    assert datetime(2026, 11, 10, 15, 30, tzinfo=UTC) < start < datetime(2026, 11, 10, 16, 0, tzinfo=UTC)
    assert 14.0 < (end - start).total_seconds() / 3600 < 15.0
    for moment in (start, end):
        assert sun_altitude(SITE.latitude, SITE.longitude, moment.timestamp()) == pytest.approx(
            -3.0, abs=0.05
        )


def test_the_interruption_rains_for_an_hour_mid_night() -> None:
    entries = weather_scenario("interruption", 36000.0)
    assert entries is not None
    scenario = WeatherScenario.from_config(entries)
    raining = [t for t in range(0, 36000, 60) if scenario.state_at(t).rain]
    assert raining[0] == 18000 and raining[-1] - raining[0] == pytest.approx(3600, abs=60)
    assert not any(scenario.state_at(t).rain for t in range(0, 36000, 600)) or raining
    for short in (600.0, 4680.0):  # a short night still gets a valid scenario
        WeatherScenario.from_config(weather_scenario("interruption", short) or [])
    assert weather_scenario("random", 100.0) is None
    assert not any(
        WeatherScenario.from_config(weather_scenario("clear", 3600.0) or []).state_at(t).rain
        for t in (0, 3600)
    )
    with pytest.raises(ValueError, match="unknown weather scenario 'hail'"):
        weather_scenario("hail", 100.0)


def test_samples_move_to_another_night_and_flats_get_one_task_per_twilight() -> None:
    flats = load_samples()["twilight-sky-flats"]
    moved = shifted_group(flats, date(2026, 11, 12))
    assert moved.requests[0].windows[0].start.day == 12
    parts = one_window_each(flats)
    assert [len(p.requests[0].windows) for p in parts] == [1, 1]
    assert parts[0].requests[0].windows[0] != parts[1].requests[0].windows[0]


def test_the_survey_fills_the_night_at_low_priority() -> None:
    groups = survey_groups(date(2026, 11, 10))
    assert len(groups) >= 10 and all(g.priority < 1 for g in groups)
