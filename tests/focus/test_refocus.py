"""Refocus triggers (pure): the FWHM rise, the temperature, the time since the focus, the filter."""

from __future__ import annotations

import pytest

from nightcrew.focus.refocus import FocusState, RefocusTriggers, refocus_cause

LAST = FocusState(time=1000.0, temperature=10.0, filter_name="V", fwhm=2.0)


def _cause(
    triggers: RefocusTriggers,
    *,
    time: float = 2000.0,
    temperature: float = 10.5,
    filter_name: str = "V",
    fwhm: float = 2.4,
) -> str | None:
    """The cause on a calm night (nothing past its limit) with one thing changed."""
    return refocus_cause(
        triggers, LAST, time=time, temperature=temperature, filter_name=filter_name, fwhm=fwhm
    )


def test_each_trigger_fires_only_when_it_is_on_and_its_limit_is_passed() -> None:
    every = RefocusTriggers(fwhm_rise=0.25, temperature_change=1.5, interval=3600.0, filter_change=True)
    assert _cause(every) is None
    assert _cause(every, fwhm=2.6) == "FWHM 2.60 is 30 % above 2.00 after the last focus"
    assert _cause(every, temperature=8.0) == "temperature 8.0 °C, 10.0 °C at the last focus"
    assert _cause(every, time=4700.0) == "3700 s since the last focus"
    assert _cause(every, filter_name="R") == "filter R, the last focus was in V"
    none = RefocusTriggers()
    assert not none.any and every.any
    assert {_cause(none, fwhm=9.0), _cause(none, temperature=0.0), _cause(none, time=1e6)} == {None}
    assert _cause(none, filter_name="R") is None


def test_what_is_not_known_never_fires() -> None:
    every = RefocusTriggers(fwhm_rise=0.1, temperature_change=0.5, filter_change=True)
    unknown = FocusState(time=0.0)
    assert refocus_cause(every, unknown, time=10.0, temperature=30.0, filter_name=None, fwhm=9.0) is None


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"fwhm_rise": -0.1}, "fwhm_rise must be >= 0, got -0.1"),
        ({"interval": "1h"}, "interval must be a number >= 0, got '1h'"),
        ({"filter_change": "yes"}, "filter_change must be true or false, got 'yes'"),
    ],
)
def test_triggers_that_make_no_sense_are_refused(options: dict[str, object], message: str) -> None:
    with pytest.raises(ValueError, match=message):
        RefocusTriggers(**options)  # type: ignore[arg-type]
