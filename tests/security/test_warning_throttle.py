"""One warning line per sender and event a minute, with the count of those held back (pure)."""

from __future__ import annotations

from nightcrew.security import WarningThrottle


def test_one_line_per_key_and_period_then_the_count_held_back() -> None:
    now = [0.0]
    throttle = WarningThrottle(60.0, now=lambda: now[0])
    assert throttle.due(("observer", "SafetyClearedEvent")) == 0  # the first: at once
    assert throttle.due(("observer", "BadWeatherEvent")) == 0  # another event: its own line
    for _ in range(1000):  # a flood within the minute: no line
        now[0] += 0.01
        assert throttle.due(("observer", "SafetyClearedEvent")) is None
    assert throttle.due(("stranger", "SafetyClearedEvent")) == 0  # another sender: its own line
    now[0] = 60.0
    assert throttle.due(("observer", "SafetyClearedEvent")) == 1000  # the next line tells the count
    assert throttle.due(("observer", "SafetyClearedEvent")) is None
