"""bench/night_breakdown.py: every second of the good-weather dark time gets one label."""

from __future__ import annotations

import importlib.util
from datetime import UTC, datetime
from pathlib import Path
from types import ModuleType
from typing import Any

from nightcrew.report import Frame, Night, Record

#: 22:00 UTC on the sample night at the sim's site: the Sun is far below -12 degrees.
T0 = datetime(2026, 11, 10, 22, tzinfo=UTC).timestamp()
SITE = {"latitude": 51.56, "longitude": 9.94}


def _bench_module() -> ModuleType:
    path = Path(__file__).parents[2] / "bench" / "night_breakdown.py"
    spec = importlib.util.spec_from_file_location("night_breakdown", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _record(t: float, kind: str, sender: str = "", **data: Any) -> Record:
    return Record(T0 + t, kind, sender, data)


def _frame(t: float, exposure_time: float, image_type: str) -> Frame:
    return Frame(f"{t}.fits", T0 + t, exposure_time, image_type, "V", "", None, None)


def test_each_second_counts_once_in_the_first_label_that_applies() -> None:
    night = Night(
        records=[
            _record(0, "GoodWeatherEvent", "weather"),
            _record(100, "RoofOpenedEvent", "roof"),
            _record(200, "TaskStartedEvent", "mastermind", id="1", name="M31"),
            _record(200, "MotionStatusChangedEvent", "telescope", status="slewing"),
            _record(230, "MotionStatusChangedEvent", "telescope", status="tracking"),
            _record(300, "ExposureStatusChangedEvent", "camera", current="exposing"),
            _record(600, "ExposureStatusChangedEvent", "camera", current="readout"),
            _record(610, "ExposureStatusChangedEvent", "camera", current="idle"),
            _record(700, "TaskFinishedEvent", "mastermind", id="1", name="M31"),
            _record(1000, "RoofClosingEvent", "roof"),
        ],
        frames=[_frame(300, 300, "object"), _frame(800, 10, "focus"), _frame(850, 10, "focus")],
    )
    spent = _bench_module().breakdown(night, **SITE)
    assert {label: round(seconds) for label, seconds in spent.items()} == {
        "exposing focus": 20,
        "exposing object": 300,
        "readout": 10,
        "slew": 30,
        "roof not open": 100,
        "focus run, between frames": 40,
        "in a task, camera idle": 160,  # 200-700 less the slew, exposure and read-out
        "no task running": 340,  # 100-200 and 700-1000 less the focus run
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
    spent = _bench_module().breakdown(night, **SITE)
    assert round(sum(spent.values())) == 700 and round(spent["roof not open"]) == 700
