"""``nightcrew sim``: a shortened robotic night with rain, judged from what it recorded.

One run for all tests here: 2.5 clock hours from 18:00 UTC (dark) with the ``interruption``
scenario, i.e. rain from 75 min on for 37.5 min, and the weather judged good again 15 min after
(as at the start: the weather module wants 15 good minutes before it says so).
Every number comes from the recorded events and FITS headers through :mod:`nightcrew.report`,
the same code the night report uses. Times are clock times.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.report import NightNumbers, night_numbers, read_night, write_report

HOURS = 2.5
#: The night runs in the first test's fixture: a minute or two of wall time, more on a busy machine.
pytestmark = pytest.mark.timeout(900)


@pytest.fixture(scope="module")
def night(tmp_path_factory: pytest.TempPathFactory) -> tuple[int, Path, NightNumbers]:
    out = tmp_path_factory.mktemp("night")
    code = main(
        ["sim", "--out", str(out), "--start", "18:00", "--hours", str(HOURS), "--weather", "interruption"]
    )
    numbers = night_numbers(read_night(out), latitude=51.56, longitude=9.94)
    return code, out, numbers


def test_the_night_runs_to_its_end_and_takes_science_frames(night: tuple[int, Path, NightNumbers]) -> None:
    code, out, _ = night
    assert code == 0
    frames = read_night(out).frames
    assert sum(1 for f in frames if f.image_type == "object") >= 5
    assert all(f.task for f in frames if f.image_type == "object"), "science frames name their task"


def test_no_exposure_while_the_roof_is_closed(night: tuple[int, Path, NightNumbers]) -> None:
    _, _, numbers = night
    assert numbers.science_frames_while_closed == 0
    assert numbers.light_frames_while_closed == 0


def test_the_roof_closes_within_a_minute_of_bad_weather(night: tuple[int, Path, NightNumbers]) -> None:
    _, _, numbers = night
    assert len(numbers.roof_close_delays_s) == 1, "the rain found the roof open once"
    assert numbers.roof_close_delays_s[0] <= 60.0


def test_every_task_ends_done_or_failed_with_a_reason(night: tuple[int, Path, NightNumbers]) -> None:
    _, _, numbers = night
    assert numbers.tasks, "tasks ran"
    assert numbers.tasks_without_reason == ()
    interrupted = [t for t in numbers.tasks if "bad weather" in t.reason]
    assert interrupted, "the rain interrupted the task running then"


def test_the_roof_is_open_most_of_the_good_dark_time(night: tuple[int, Path, NightNumbers]) -> None:
    _, _, numbers = night
    assert numbers.good_dark_s > 2400.0
    assert numbers.roof_open_fraction >= 0.9, f"{100 * numbers.roof_open_fraction:.1f} %"
    # The camera's shutter: exposures cover most of it; the rest is read-outs, slews, the focus
    # series at the start and the roof opening twice (the telescope slews meanwhile). The exposures
    # cut short by the rain and by the end of the run are stopped and kept (CUTSHORT), so their
    # open time counts: 92.6 % on the virtual clock (88.4 % when they were aborted and lost).
    assert numbers.shutter_open_fraction >= 0.9, f"{100 * numbers.shutter_open_fraction:.1f} %"


def test_the_report_has_every_section(night: tuple[int, Path, NightNumbers]) -> None:
    _, out, _ = night
    page = (out / "report.html").read_text(encoding="utf-8")
    titles = ("Summary", "Timeline", "Where the good-weather dark time went", "Tasks", "Scheduler")
    for title in (*titles, "Focus", "Sky flats", "Guiding", "Frames"):
        assert f"<h2>{title}" in page
    assert page.count("<svg") >= 2 and "<script" not in page
    thumbnails = list((out / "thumbnails").glob("*.png"))
    assert len(thumbnails) == len(read_night(out).frames)
    assert write_report(out) == out / "report.html"  # again, from the files alone


def test_nightcrew_report_rewrites_the_report_and_refuses_a_directory_without_a_night(
    night: tuple[int, Path, NightNumbers], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    _, out, _ = night
    assert main(["report", str(out)]) == 0
    assert capsys.readouterr().out.strip() == str(out / "report.html")
    assert main(["report", str(tmp_path)]) == 2
    assert "holds no night (no events.jsonl)" in capsys.readouterr().err
