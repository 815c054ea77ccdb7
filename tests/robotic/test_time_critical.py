"""Time-critical and cadence requests: early starts in the plan, cadences expanded into visits."""

from __future__ import annotations

import asyncio
import copy
import re
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import pytest

from nightcrew.cli.main import main
from nightcrew.errors import InvalidArgumentError
from nightcrew.night.cadences import stored_cadences
from nightcrew.report import write_report
from nightcrew.report._data import Night as RecordedNight
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.scheduler import Night, SchedulableBlock, Scheduler, Target
from nightcrew.robotic.tasks import (
    InvalidTaskError,
    ObservationType,
    RequestGroup,
    TaskProgress,
    cadence_visit,
    parse_request_group,
    tasks_of_group,
)
from nightcrew.robotic.tasks.blocks import block_of
from nightcrew.site import Site

SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0, name="Göttingen")
START = datetime(2024, 1, 15, 17, 0, tzinfo=UTC)
CIRCUMPOLAR = Target(ra=60.0, dec=80.0)

CADENCE_GROUP: dict[str, Any] = {
    "name": "monitoring",
    "proposal": "variables",
    "requests": [
        {
            "location": {"telescope_class": "0m4"},
            "cadence": {
                "start": "2024-01-15T19:00:00Z",
                "end": "2024-01-16T03:00:00Z",
                "period": 2,
                "jitter": 1,
            },
            "configurations": [
                {
                    "type": "EXPOSE",
                    "target": {"name": "star", "ra": 60.0, "dec": 80.0},
                    "instrument_configs": [{"exposure_time": 300, "exposure_count": 2}],
                }
            ],
        }
    ],
}


def cadence_group(**changes: object) -> dict[str, Any]:
    data = copy.deepcopy(CADENCE_GROUP)
    data["requests"][0]["cadence"].update(changes)
    return data


def test_a_cadence_expands_into_one_request_per_visit_window() -> None:
    group = parse_request_group(CADENCE_GROUP)
    windows = [(r.windows[0].start.hour, r.windows[0].end.hour) for r in group.requests]
    # Centres at 19, 21, 23, 01; the one at 03 would end after the cadence's end.
    assert windows == [(18, 19), (20, 21), (22, 23), (0, 1)]
    assert all(len(r.windows) == 1 and r.cadence is not None for r in group.requests)
    # Stored and read back (as archives do), the visits stay visits.
    again = RequestGroup.model_validate(group.model_dump(mode="json"))
    assert again == group
    cadence = group.requests[2].cadence
    assert cadence is not None
    assert cadence_visit(cadence, group.requests[2].windows[0].start) == (3, 4)


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (
            {"period": 0.1, "jitter": 0.1},
            r"requests\[0\]\.cadence\.period: 0\.1 h is shorter than the request's 600 s",
        ),
        ({"end": "2024-01-15T18:00:00Z"}, r"requests\[0\]\.cadence\.end: must be after start"),
        ({"jitter": 3}, r"requests\[0\]\.cadence\.jitter: must be at most the period"),
        ({"jitter": 0.1}, r"requests\[0\]\.cadence\.jitter: a window of 0\.1 h cannot hold"),
    ],
)
def test_an_impossible_cadence_is_one_clear_error(changes: dict[str, object], message: str) -> None:
    with pytest.raises(InvalidTaskError, match=message) as caught:
        parse_request_group(cadence_group(**changes))
    assert len(caught.value.problems) == 1


def test_a_window_ending_before_it_starts_is_one_clear_error() -> None:
    data = copy.deepcopy(CADENCE_GROUP)
    request = data["requests"][0]
    del request["cadence"]
    request["windows"] = [{"start": "2024-01-15T20:00:00Z", "end": "2024-01-15T19:00:00Z"}]
    with pytest.raises(InvalidTaskError, match=r"requests\[0\]\.windows\[0\]\.end: must be after start"):
        parse_request_group(data)


def test_the_observation_type_sets_the_blocks_urgency() -> None:
    urgency = {}
    for kind in ObservationType:
        group = parse_request_group({**CADENCE_GROUP, "observation_type": kind.value})
        block = block_of(tasks_of_group(group, "g", ["t0", "t1", "t2", "t3"])[0])
        assert block is not None
        urgency[kind] = block.early_start_weight
    assert urgency[ObservationType.NORMAL] == 0.0
    assert 0.0 < urgency[ObservationType.TIME_CRITICAL] < urgency[ObservationType.RAPID_RESPONSE] <= 1.0


def test_a_time_critical_block_starts_as_early_as_its_window_allows() -> None:
    window = ((START + timedelta(hours=2), START + timedelta(hours=4)),)
    plain = SchedulableBlock("plain", 1.0, 1200.0, CIRCUMPOLAR, windows=window)
    urgent = SchedulableBlock("urgent", 1.0, 1200.0, CIRCUMPOLAR, windows=window, early_start_weight=0.2)
    scheduler = Scheduler(step_s=300.0, time_limit_s=2.0)
    night = Night(START, START + timedelta(hours=13), SITE)
    # Alone in the night, the urgent block takes the first start its window allows (plus the pad).
    slot = scheduler.schedule([urgent], night).slots[0]
    assert slot.start - window[0][0] <= timedelta(seconds=scheduler.slew_overhead_s + 300.0)
    # Sharing the window with a plain block of the same value, it goes first.
    slots = {s.task_id: s for s in scheduler.schedule([plain, urgent], night).slots}
    assert slots["urgent"].start < slots["plain"].start


def test_an_early_start_weight_out_of_range_names_the_block() -> None:
    with pytest.raises(
        InvalidArgumentError, match=r"block .b.: early_start_weight must be within 0\.\.1, got 2\.0"
    ):
        SchedulableBlock("b", 1.0, 60.0, CIRCUMPOLAR, early_start_weight=2.0)


def test_the_cadence_example_in_the_doc_adds_four_visits_and_shows_progress(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.delenv("NIGHTCREW_COMM", raising=False)
    doc = (Path(__file__).parents[2] / "docs/tasks.md").read_text()
    found = re.search(r"```yaml\n(# monitoring\.yaml.*?)```", doc, flags=re.S)
    assert found is not None
    (tmp_path / "monitoring.yaml").write_text(found.group(1))
    db = str(tmp_path / "tasks.sqlite")
    assert main(["tasks", "--db", db, "add", str(tmp_path / "monitoring.yaml")]) == 0
    assert "tasks 1, 2, 3, 4" in capsys.readouterr().out
    assert main(["tasks", "--db", db, "show", "2"]) == 0
    assert "cadence: visit 2 of 4; 4 pending" in capsys.readouterr().out.splitlines()


async def test_the_night_report_shows_each_cadence_s_progress(tmp_path: Path) -> None:
    db = tmp_path / "tasks.sqlite"
    async with SqliteTaskArchive(db, poll_interval=0) as archive:
        first, *_ = await archive.add_request_group(parse_request_group(CADENCE_GROUP))
        await archive.mark_started(first.id)
        await archive.mark_finished(first.id, TaskProgress(exposures_done=((2,),)))
    # Read where no event loop runs, as `nightcrew report` and `nightcrew sim` do.
    cadences = await asyncio.to_thread(stored_cadences, db)
    assert cadences == [("monitoring", "1 of 4 visits completed; 1 completed, 3 pending")]
    page = write_report(
        tmp_path, night=RecordedNight(records=[], frames=[]), thumbnails=False, cadences=cadences
    )
    assert "<h2>Cadences</h2>" in page.read_text() and "1 of 4 visits completed" in page.read_text()
