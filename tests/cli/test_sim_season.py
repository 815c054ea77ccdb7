"""``nightcrew sim --nights 2 --weather random``: two nights on the one engine and the season's report.

Each night is an hour and a half of clock time (``--start 21:00 --hours 1.5``) so the test stays short;
the numbers are checked against each night's own records.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.report import night_site, read_night, season_night


@pytest.fixture(scope="module")
def season(tmp_path_factory: pytest.TempPathFactory) -> tuple[int, Path, str]:
    out = tmp_path_factory.mktemp("season")
    code = main(
        [
            "sim",
            "--out",
            str(out),
            "--nights",
            "2",
            "--weather",
            "random",
            "--seed",
            "4",
            "--start",
            "21:00",
            "--hours",
            # Astronomical night begins at ~21:14; the time-critical Algol light curve (45 min of
            # cycling, planned first) must be able to end before the run does, or no task is done.
            "1.5",
        ]
    )
    return code, out, (out / "season.md").read_text(encoding="utf-8")


@pytest.mark.timeout(900)
def test_two_nights_each_in_its_own_directory_without_frames(season: tuple[int, Path, str]) -> None:
    code, out, _ = season
    assert code == 0
    nights = sorted(p.name for p in out.glob("night-*"))
    assert nights == ["night-2026-11-10", "night-2026-11-11"]
    for name in nights:
        assert (out / name / "events.jsonl").is_file() and (out / name / "report.html").is_file()
        assert not (out / name / "frames").exists()  # dropped without --frames


@pytest.mark.timeout(900)
def test_the_season_report_holds_each_nights_numbers_and_the_totals(season: tuple[int, Path, str]) -> None:
    _, out, table = season
    summary = json.loads((out / "season.json").read_text(encoding="utf-8"))
    rows = summary["nights"]
    assert [row["night"] for row in rows] == ["2026-11-10", "2026-11-11"]
    for row in rows:
        night = read_night(out / f"night-{row['night']}")
        latitude, longitude = night_site(night)
        again = season_night(row["night"], night, latitude=latitude, longitude=longitude)
        # Frames are gone, so only what the records say can be recomputed.
        assert row["bad_weather_onsets"] == again.bad_weather_onsets
        assert tuple(row["roof_close_delays_s"]) == again.roof_close_delays_s
        assert row["tasks_done"] == again.tasks_done and row["tasks_failed"] == again.tasks_failed
        # The first quarter hour the weather is not yet known to be good.
        assert 0.5 * 3600 < row["good_dark_s"] <= 1.5 * 3600 or row["bad_weather_onsets"] > 0
        assert row["objective"] is not None and row["objective"] <= row["bound"] + 1e-9
    assert summary["tasks_done"] == sum(row["tasks_done"] for row in rows) > 0
    assert summary["good_dark_h"] == pytest.approx(sum(row["good_dark_s"] for row in rows) / 3600)
    assert summary["science_frames_while_closed"] == 0
    assert all(d <= 60.0 for row in rows for d in row["roof_close_delays_s"])
    assert table.count("\n| 2026-11-1") == 2 and "**all 2**" in table and "Roof-close delays" in table
    # Where the dark time went: every second once, the exposing part is the shutter's.
    for row in rows:
        spent = row["dark_time"]
        assert sum(spent.values()) == pytest.approx(row["good_dark_s"], abs=1e-6)
        exposing = sum(v for k, v in spent.items() if k.startswith("exposing "))
        assert exposing == pytest.approx(row["shutter_open_s"], abs=1e-6)
    assert "Where the good-weather dark time went" in table and "| roof opening or closing |" in table
