"""Where the good-weather dark time went, and each task's time to its first science frame."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import pytest

from nightcrew.report import Acquisition, Frame, Night, Record, night_numbers
from nightcrew.report._sections import time_budget_section
from nightcrew.report._time_budget import BUDGET_LABELS, acquisitions, time_budget

#: 22:00 UTC on the sample night at the sim's site: the Sun is far below -12 degrees.
T0 = datetime(2026, 11, 10, 22, tzinfo=UTC).timestamp()
SITE = {"latitude": 51.56, "longitude": 9.94}


def _record(t: float, kind: str, sender: str = "", **data: Any) -> Record:
    return Record(T0 + t, kind, sender, data)


def _frame(t: float, exposure_time: float, image_type: str) -> Frame:
    return Frame(f"{t}.fits", T0 + t, exposure_time, image_type, "V", "", None, None)


def _camera(t: float, current: str) -> Record:
    return _record(t, "ExposureStatusChangedEvent", "camera", current=current)


def _telescope(t: float, status: str) -> Record:
    return _record(t, "MotionStatusChangedEvent", "telescope", status=status)


def _roof(t: float, status: str) -> Record:
    return _record(t, "MotionStatusChangedEvent", "roof", status=status)


def _filters(t: float, status: str) -> Record:
    return _record(t, "MotionStatusChangedEvent", "filters", status=status)


def test_each_second_counts_once_in_the_first_label_that_applies() -> None:
    night = Night(
        records=[
            _record(0, "GoodWeatherEvent", "weather"),
            _roof(40, "moving"),
            _roof(100, "idle"),
            _record(100, "RoofOpenedEvent", "roof"),
            _record(200, "TaskStartedEvent", "mastermind", id="1", name="M31"),
            _telescope(200, "slewing"),
            _telescope(230, "tracking"),
            _filters(230, "moving"),
            _filters(233, "idle"),
            _camera(300, "exposing"),
            _camera(600, "readout"),
            _camera(610, "idle"),
            _camera(620, "exposing"),  # cut short (by the task's end): no frame
            _camera(650, "idle"),
            _record(700, "TaskFinishedEvent", "mastermind", id="1", name="M31"),
            _telescope(900, "parking"),
            _telescope(920, "parked"),
            _record(1000, "RoofClosingEvent", "roof"),
        ],
        frames=[
            _frame(300, 300, "object"),
            _frame(800, 10, "focus"),
            _frame(850, 10, "focus"),
            _frame(950, 20, "dark"),  # shutter closed: not exposing the sky
        ],
    )
    spent = time_budget(night, **SITE)
    assert list(spent) == ["exposing focus", "exposing object", *BUDGET_LABELS]
    assert {label: round(seconds) for label, seconds in spent.items()} == {
        "exposing focus": 20,
        "exposing object": 300,
        "dark and bias frames": 20,
        "exposing, frame not kept": 30,
        "readout": 10,
        "slew": 50,  # 200-230 and the parking at 900-920
        "roof opening or closing": 60,
        "roof closed": 40,
        "filter change": 3,
        "focus run, between frames": 40,
        "in a task, camera idle": 127,  # 200-700 less the slew, filter change, exposures, read-out
        "no task running": 300,  # 100-200 and 700-1000 less the focus run, the parking, the dark
    }
    assert round(sum(spent.values())) == 1000


def test_bad_weather_is_not_good_dark_time() -> None:
    night = Night(
        records=[
            _record(0, "GoodWeatherEvent", "weather"),
            _record(100, "BadWeatherEvent", "weather"),
            _record(400, "GoodWeatherEvent", "weather"),
            _record(1000, "RoofClosedEvent", "roof"),
        ]
    )
    spent = time_budget(night, **SITE)
    assert round(sum(spent.values())) == 700 and round(spent["roof closed"]) == 700


def test_twilight_is_not_dark_time() -> None:
    # 16:00-17:00 UTC: the Sun sets at about 15:40 and reaches -12 degrees at about 16:55.
    dusk = datetime(2026, 11, 10, 16, tzinfo=UTC).timestamp() - T0
    night = Night(records=[_record(dusk, "GoodWeatherEvent", "weather"), _record(dusk + 3600, "Tick")])
    dark_s = sum(time_budget(night, **SITE).values())
    assert 60 <= dark_s <= 900
    assert sum(time_budget(night, **SITE, sun_limit=-18.0).values()) == 0


def test_acquisition_is_the_time_to_the_first_science_exposure_of_each_run() -> None:
    night = Night(
        records=[
            _record(0, "TaskStartedEvent", "mastermind", id="7", name="M13"),
            _telescope(0, "slewing"),
            _telescope(40, "tracking"),
            _camera(60, "exposing"),  # an acquisition frame: not written
            _camera(70, "readout"),
            _camera(75, "idle"),
            _camera(300, "exposing"),
            _camera(600, "readout"),
            _camera(606, "idle"),
            _camera(610, "exposing"),
            _camera(910, "readout"),
            _camera(916, "idle"),
            _record(920, "TaskFinishedEvent", "mastermind", id="7", name="M13"),
            _record(1000, "TaskStartedEvent", "mastermind", id="8", name="Flats"),
            _record(1200, "TaskFinishedEvent", "mastermind", id="8", name="Flats"),
            _record(1300, "TaskStartedEvent", "mastermind", id="9", name="M39"),
            _telescope(1300, "slewing"),
            _telescope(1320, "tracking"),
            _record(1700, "TaskFailedEvent", "mastermind", id="9", name="M39", reason="not acquired"),
        ],
        frames=[
            _frame(300, 300, "object"),
            _frame(610, 300, "object"),
            _frame(1100, 5, "skyflat"),
            _frame(1330, 10, "acquisition"),  # M39's: an acquisition, not a calibration
        ],
    )
    m13, m39 = acquisitions(night)
    assert (m13.task_id, m13.name) == ("7", "M13") and m13.seconds == pytest.approx(300.0)
    assert m13.slewing_s == pytest.approx(40.0) and m13.camera_busy_s == pytest.approx(15.0)
    # Failed before any science frame: no time to it, but its slew until the end is counted.
    assert (m39.task_id, m39.seconds, m39.first_science) == ("9", None, None)
    assert m39.slewing_s == pytest.approx(20.0) and m39.camera_busy_s == 0.0


def test_a_frame_of_the_previous_run_is_not_the_first_of_the_next() -> None:
    night = Night(
        records=[
            _record(0, "TaskStartedEvent", "mastermind", id="1", name="a"),
            _record(400, "TaskFinishedEvent", "mastermind", id="1", name="a"),
            _record(400, "TaskStartedEvent", "mastermind", id="2", name="b"),
            _record(700, "TaskFinishedEvent", "mastermind", id="2", name="b"),
        ],
        frames=[_frame(100, 300, "object"), _frame(520, 60, "object")],
    )
    first, second = acquisitions(night)
    assert (first.task_id, second.task_id) == ("1", "2")
    assert first.seconds == pytest.approx(100.0) and second.seconds == pytest.approx(120.0)


def test_the_budget_adds_up_to_the_night_numbers() -> None:
    night = Night(
        records=[
            _record(0, "GoodWeatherEvent", "weather"),
            _record(50, "RoofOpenedEvent", "roof"),
            _record(60, "TaskStartedEvent", "mastermind", id="1", name="a"),
            _record(400, "BadWeatherEvent", "weather"),
            _record(410, "RoofClosingEvent", "roof"),
            _record(420, "TaskFailedEvent", "mastermind", id="1", name="a", reason="rain"),
            _record(900, "GoodWeatherEvent", "weather"),
            _record(2000, "ModuleClosedEvent", "mastermind"),
        ],
        frames=[_frame(100, 120, "object"), _frame(300, 150, "object"), _frame(1000, 30, "skyflat")],
    )
    spent = time_budget(night, **SITE)
    numbers = night_numbers(night, **SITE)
    assert sum(spent.values()) == pytest.approx(numbers.good_dark_s)
    exposing = sum(v for k, v in spent.items() if k.startswith("exposing "))
    assert exposing == pytest.approx(numbers.shutter_open_s)
    assert spent["exposing object"] == pytest.approx(220.0)  # 100-220 and 300-400, the rain cuts it


def test_the_report_section_shows_each_label_with_time_and_each_acquisition() -> None:
    spent = {"exposing object": 2400.0, "exposing skyflat": 0.0, "slew": 600.0, "no task running": 600.0}
    runs = [
        Acquisition("7", "M13", T0, T0 + 330.0, slewing_s=40.0, camera_busy_s=200.0),
        Acquisition("9", "M39", T0 + 900, None, slewing_s=20.0, camera_busy_s=0.0),
    ]
    page = time_budget_section(spent, runs)
    assert "<td>exposing object</td><td>40.0</td><td>66.7</td>" in page
    assert "<td>slew</td><td>10.0</td><td>16.7</td>" in page
    assert "<td>all</td><td>60.0</td><td>100</td>" in page
    assert "skyflat" not in page, "labels without time are left out"
    assert page.count("<rect") == 1 + 3, "a bar: its background, then a box per label with time"
    assert "<td>M13</td><td>22:00</td><td>330</td><td>40</td><td>200</td><td>90</td>" in page
    assert "<td>M39</td><td>22:15</td><td>no science frame</td><td>20</td><td>0</td><td></td>" in page
    assert time_budget_section({"no task running": 0.0}, runs) == "<p><em>no good-weather dark time</em></p>"
