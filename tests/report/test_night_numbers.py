"""The night's numbers from records: intervals, roof-close delays, task outcomes (pure, no files)."""

from __future__ import annotations

from typing import Any

import pytest

from nightcrew.report import Record
from nightcrew.report._data import (
    Frame,
    Night,
    bad_weather_intervals,
    describe_frames,
    frame_of_header,
    roof_open_intervals,
    task_runs,
)
from nightcrew.report._metrics import (
    exposures_while_closed,
    intersect,
    night_numbers,
    roof_close_delays,
    subtract,
)
from nightcrew.report._svg import Band, Series, bands, nice_ticks, xy_chart

T0 = 1794340800.0  # 2026-11-10T20:00:00Z, dark at the sim's site


def rec(t: float, kind: str, **data: Any) -> Record:
    return Record(T0 + t, kind, "test", data)


def frame(start: float, exposure: float, image_type: str = "object") -> Frame:
    return Frame(f"f{start:g}.fits", T0 + start, exposure, image_type, "V", "", None, None)


RECORDS = [
    rec(0, "GoodWeatherEvent", eta=None),
    rec(10, "RoofOpenedEvent"),
    rec(20, "TaskStartedEvent", id="1", name="a"),
    rec(500, "TaskFinishedEvent", id="1", name="a"),
    rec(510, "TaskStartedEvent", id="2", name="b"),
    rec(1000, "BadWeatherEvent", reason="rain"),
    rec(1001, "RoofClosingEvent"),
    rec(
        1003, "TaskFailedEvent", id="2", name="b", reason="interrupted by bad weather: 1 of 3 exposures done"
    ),
    rec(1046, "RoofClosedEvent"),
    rec(2000, "GoodWeatherEvent", eta="2026-11-10T20:48:20+00:00"),  # good from 2900 s
    rec(2950, "RoofOpenedEvent"),
    rec(3600, "ModuleClosedEvent"),
]


def test_roof_and_weather_intervals() -> None:
    end = T0 + 3600
    assert roof_open_intervals(RECORDS, end) == [(T0 + 10, T0 + 1001), (T0 + 2950, end)]
    assert bad_weather_intervals(RECORDS, end) == [(T0 + 1000, T0 + 2900)]


def test_unknown_weather_before_the_first_verdict_counts_as_bad() -> None:
    records = [rec(0, "ModuleOpenedEvent"), rec(100, "GoodWeatherEvent")]
    assert bad_weather_intervals(records, T0 + 200) == [(T0, T0 + 100)]


def test_roof_close_delay_counts_from_bad_weather_with_the_roof_open() -> None:
    assert roof_close_delays(RECORDS) == [pytest.approx(46.0)]
    closed_already = [rec(0, "RoofClosedEvent"), rec(10, "BadWeatherEvent")]
    assert roof_close_delays(closed_already) == []


def test_task_runs_end_done_or_failed_with_their_reason() -> None:
    runs = task_runs(RECORDS)
    assert [(r.task_id, r.outcome) for r in runs] == [("1", "done"), ("2", "failed")]
    assert runs[1].reason.startswith("interrupted by bad weather")


def test_exposures_while_closed_are_light_frames_outside_roof_open_intervals() -> None:
    roof = [(T0 + 10, T0 + 1001)]
    frames = [frame(20, 300), frame(990, 30), frame(1100, 60, "dark"), frame(1100, 60, "object")]
    assert [f.start - T0 for f in exposures_while_closed(frames, roof)] == [990, 1100]


def test_interval_arithmetic() -> None:
    assert intersect([(0, 10), (20, 30)], [(5, 25)]) == [(5, 10), (20, 25)]
    assert subtract([(0, 100)], [(10, 20), (50, 200)]) == [(0, 10), (20, 50)]


def test_night_numbers_shutter_open_is_part_of_the_good_dark_time() -> None:
    night = Night(records=RECORDS, frames=[frame(20, 480), frame(2960, 600)])
    numbers = night_numbers(night, latitude=51.56, longitude=9.94)
    # Good and dark: 0..1000 and 2900..3600 = 1700 s; exposed 20..500 and 2960..3560 = 1080 s.
    assert numbers.good_dark_s == pytest.approx(1700.0)
    assert numbers.roof_open_s == pytest.approx(990.0 + 650.0)  # 10..1000 and 2950..3600
    assert numbers.shutter_open_s == pytest.approx(1080.0)
    assert numbers.light_frames_while_closed == 0
    assert numbers.tasks_without_reason == ()


def test_a_frame_from_its_header() -> None:
    header = {"DATE-OBS": "2026-11-10T20:00:00.000", "EXPTIME": 30.0, "IMAGETYP": "object", "GUIDRMS": 0.4}
    f = frame_of_header("a.fits", header)
    assert (f.start, f.end, f.light, f.guide_rms) == (T0, T0 + 30, True, 0.4)


def test_svg_charts() -> None:
    assert nice_ticks(0.0, 9.0) == [0.0, 2.0, 4.0, 6.0, 8.0]
    chart = xy_chart([Series("s", [(1.0, 2.0), (2.0, 4.0)], line=True)], x_label="x <1>", y_label="y")
    assert chart.startswith("<svg") and "polyline" in chart and "x &lt;1&gt;" in chart
    assert "no data" in xy_chart([Series("s", [(1.0, -1.0)])], x_label="x", y_label="y", log_y=True)
    timeline = bands(
        [Band("Roof", [(0.0, 5.0, "open", "#0f0")])], start=0, end=10, x_format=str, x_ticks=[0, 5]
    )
    assert "<title>open</title>" in timeline


def test_the_frames_are_told_apart_by_what_they_are_for() -> None:
    types = ["object", "bias", "dark", "skyflat", "focus", "focus", "acquisition", "guiding", ""]
    frames = [frame(10.0 * n, 1.0, image_type) for n, image_type in enumerate(types)]
    assert describe_frames(frames) == (
        "9 frames (4 science and calibration, 3 focus and acquisition, 1 without IMAGETYP, 1 guiding)"
    )
    assert describe_frames([]) == "0 frames (0 science and calibration, 0 focus and acquisition)"
