"""HeartbeatMonitor: who is overdue, and why."""

from __future__ import annotations

import pytest

from nightcrew.modules.safety import HeartbeatMonitor


def test_every_module_gets_its_whole_limit_from_the_start() -> None:
    monitor = HeartbeatMonitor({"weather": 60, "mastermind": 120}, start=1000.0)
    assert monitor.overdue(1060.0) == {}
    assert monitor.overdue(1061.0) == {"weather": "weather: no answer for 61 s (limit 60 s)"}


def test_a_good_beat_resets_and_a_problem_is_named() -> None:
    monitor = HeartbeatMonitor({"weather": 60}, start=0.0)
    monitor.beat("weather", 50.0)
    monitor.beat("weather", 80.0, "error state (station down)")
    assert monitor.overdue(110.0) == {}
    assert monitor.overdue(111.0) == {"weather": "weather: error state (station down) for 61 s (limit 60 s)"}
    monitor.beat("weather", 112.0)
    assert monitor.overdue(120.0) == {}


def test_limits_must_be_positive() -> None:
    with pytest.raises(ValueError, match="the limit of 'weather' must be > 0 seconds, got 0"):
        HeartbeatMonitor({"weather": 0}, start=0.0)
