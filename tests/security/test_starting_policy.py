"""The starting policy (`nightcrew init`, `nightcrew server init`): what each role may do."""

from __future__ import annotations

from nightcrew.events import RapidResponseEvent, hardware_event_names
from nightcrew.security import parse_policy, starting_policy

MODULES = ["roof", "camera", "focus", "focusmodel", "weather", "watchdog"]
POLICY = parse_policy(starting_policy(MODULES, {"operator": "operator", "observer": "observer"}))


def test_observers_read_and_change_nothing() -> None:
    for method in ("get_state", "get_config_value", "is_ready", "list_filters", "has_image"):
        assert POLICY.allows("observer", "camera", method, None), method
    for method in ("reset_error", "set_config_value", "set_exposure_time", "grab_data", "open_roof"):
        assert not POLICY.allows("observer", "camera", method, None), method
    assert POLICY.allows("operator", "roof", "open_roof", None)
    assert not POLICY.allows("outsider", "camera", "get_state", None)


def test_hardware_events_from_the_safety_modules_focus_results_from_modules_only() -> None:
    for name in hardware_event_names():
        assert POLICY.accepts_event("watchdog", name, moves_hardware=True)
        # The right to pre-empt (a rapid-response request) is the modules' and the operators' too.
        rapid = name == RapidResponseEvent.event_name()
        assert POLICY.accepts_event("camera", name, moves_hardware=True) is rapid
        assert POLICY.accepts_event("operator", name, moves_hardware=True) is rapid
        assert not POLICY.accepts_event("observer", name, moves_hardware=True)
    assert POLICY.accepts_event("focus", "FocusFoundEvent")
    assert not POLICY.accepts_event("observer", "FocusFoundEvent")
    assert not POLICY.accepts_event("operator", "FocusFoundEvent")
    assert POLICY.accepts_event("observer", "TestEvent")  # events nobody acts on: from anyone
