"""The twilight planner: flat-field combinations in the order their openings close, by priority."""

from __future__ import annotations

import pytest

from nightcrew.errors import ConfigError
from nightcrew.flatfield import ExposureTimeFunctions, FlatLimits, FlatTask, TwilightPlanner, plan_twilight

#: B needs exp(0.92 * 1.5) = 4x the exposure of R at the same solar altitude.
FUNCTIONS = ExposureTimeFunctions(
    {
        "R": {"1x1": "exp(-0.92*(h + 4.0))"},
        "B": {"1x1": "exp(-0.92*(h + 2.5))"},
        "Ha": {"1x1": "exp(-0.92*(h + 40))"},  # always far too short an exposure: never open
    }
)
LIMITS = FlatLimits(min_exposure=1.0, max_exposure=30.0)
R, B = FlatTask("R", (1, 1), 30), FlatTask("B", (1, 1), 30)


def dusk(t: float) -> float:
    """The Sun sinks from -2° by 0.25° a minute."""
    return -2.0 - t / 240.0


def dawn(t: float) -> float:
    """The Sun rises from -12° by 0.25° a minute."""
    return -12.0 + t / 240.0


def test_at_dusk_the_filter_needing_long_exposures_goes_first_though_listed_second() -> None:
    plan = plan_twilight([R, B], FUNCTIONS, LIMITS, dusk, 0.0, overhead=5.0)
    assert [p.task.filter_name for p in plan] == ["B", "R"]
    assert all(p.fits for p in plan)
    b, r = plan
    assert b.closes is not None and r.closes is not None and b.closes < r.closes
    for planned in plan:
        assert planned.start is not None and planned.end is not None
        assert planned.opens is not None and planned.closes is not None
        assert planned.opens <= planned.start < planned.end <= planned.closes + 30.0
    # Taken in the listed order, B would start after R and no longer fit.
    (r_alone,) = plan_twilight([R], FUNCTIONS, LIMITS, dusk, 0.0, overhead=5.0)
    assert r_alone.end is not None
    (b_after_r,) = plan_twilight([B], FUNCTIONS, LIMITS, dusk, r_alone.end, overhead=5.0)
    assert not b_after_r.fits


def test_at_dawn_the_filter_needing_short_exposures_goes_first() -> None:
    plan = plan_twilight([B, R], FUNCTIONS, LIMITS, dawn, 0.0, overhead=5.0)
    assert [p.task.filter_name for p in plan] == ["R", "B"]
    assert all(p.fits for p in plan)


def test_when_not_all_fit_the_higher_priority_is_admitted_and_the_rest_comes_last() -> None:
    many_r, many_b = FlatTask("R", (1, 1), 80), FlatTask("B", (1, 1), 80)
    plan = plan_twilight([many_r, many_b], FUNCTIONS, LIMITS, dusk, 0.0, overhead=5.0)
    assert [(p.task.filter_name, p.fits) for p in plan] == [("R", True), ("B", False)]
    plan = plan_twilight([many_b, many_r], FUNCTIONS, LIMITS, dusk, 0.0, overhead=5.0)
    assert [(p.task.filter_name, p.fits) for p in plan] == [("B", True), ("R", False)]


def test_a_combination_never_within_the_limits_is_planned_last_without_an_opening() -> None:
    ha = FlatTask("Ha", (1, 1), 5)
    plan = plan_twilight([ha, R], FUNCTIONS, LIMITS, dusk, 0.0)
    assert [p.task.filter_name for p in plan] == ["R", "Ha"]
    assert plan[1].opens is None and plan[1].start is None and not plan[1].fits


def test_a_missing_function_and_bad_limits_are_named() -> None:
    with pytest.raises(ValueError, match="no exposure-time function for filter V"):
        plan_twilight([FlatTask("V", (1, 1), 5)], FUNCTIONS, LIMITS, dusk, 0.0)
    with pytest.raises(ConfigError, match="min_exposure"):
        TwilightPlanner({"R": {"1x1": "exp(-h)"}}, min_exposure=10.0, max_exposure=5.0)
    with pytest.raises(ConfigError, match="overhead"):
        TwilightPlanner({"R": {"1x1": "exp(-h)"}}, overhead=-1.0)
