"""``nightcrew tasks``: defaults shown, unknown fields refused, ``why``, ``schema``, telling the scheduler."""

from __future__ import annotations

import json
from datetime import UTC, datetime
from pathlib import Path

import pytest
import yaml

from nightcrew.cli.main import main
from nightcrew.cli.tasks import announce_change
from nightcrew.modules.robotic import SchedulerModule
from nightcrew.robotic.archives import DEFAULT_TASKS_DB, SqliteTaskArchive
from nightcrew.robotic.samples import load_samples, sample_paths
from nightcrew.robotic.tasks import request_group_schema
from nightcrew.testing import Observatory

SITE_FILE = Path(__file__).parents[2] / "examples/sim/shared/site.yaml"


def _sample(stem: str) -> str:
    return str(next(path for path in sample_paths() if path.stem == stem))


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Each test in its own observatory directory, with no database, comm or site from outside."""
    monkeypatch.chdir(tmp_path)
    for name in ("NIGHTCREW_TASKS_DB", "NIGHTCREW_COMM", "NIGHTCREW_SITE"):
        monkeypatch.delenv(name, raising=False)


def test_add_prints_the_defaults_it_filled_in_and_uses_tasks_sqlite_here(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["tasks", "add", _sample("m15-globular-cluster")]) == 0
    out = capsys.readouterr().out.splitlines()
    assert (tmp_path / DEFAULT_TASKS_DB).is_file() and DEFAULT_TASKS_DB == "tasks.sqlite"
    assert out[0] == "added 'M15 globular cluster' (group 1): task 1"
    assert out[1] == "  defaults filled in:"
    excluding = "  (can keep a target out of the plan)"
    assert f"    requests[0].configurations[0].constraints.min_lunar_distance: 30.0{excluding}" in out
    assert f"    requests[0].configurations[0].constraints.max_sun_altitude: -12.0{excluding}" in out
    assert "    requests[0].configurations[0].target.epoch: 2000.0" in out
    assert "    requests[0].configurations[0].constraints.max_airmass: 1.6" not in out  # the file gives it
    assert (
        out[-1] == "the scheduler will see it at its next poll (no --comm or $NIGHTCREW_COMM to tell it now)"
    )


def test_an_unknown_field_is_one_line_naming_it_and_the_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = yaml.safe_load(Path(_sample("m15-globular-cluster")).read_text())
    data["requests"][0]["configurations"][0]["constraints"]["min_lunar_distanse"] = 10
    typo = tmp_path / "typo.yaml"
    typo.write_text(yaml.safe_dump(data))
    assert main(["tasks", "add", str(typo)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.splitlines() == [
        f"nightcrew: error: {typo}: invalid request group:"
        " requests[0].configurations[0].constraints.min_lunar_distanse: unknown field; nothing was stored"
    ]
    assert main(["tasks", "list"]) == 0
    assert "(no tasks)" in capsys.readouterr().out


def test_why_for_an_unknown_id_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["tasks", "add", _sample("m15-globular-cluster")]) == 0
    capsys.readouterr()
    assert main(["tasks", "why", "42", "--site", str(SITE_FILE)]) == 1
    assert capsys.readouterr().err.splitlines() == ["nightcrew: error: no task '42' in tasks.sqlite"]


def test_why_says_when_a_task_is_planned_or_why_not(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(["tasks", "add", _sample("m15-globular-cluster"), _sample("twilight-sky-flats")]) == 0
    (tmp_path / "site.yaml").write_text(SITE_FILE.read_text())  # found in the observatory directory
    capsys.readouterr()
    assert main(["tasks", "why", "1", "--night", "2026-11-10"]) == 0
    out = capsys.readouterr().out.strip()
    assert (
        out.startswith("task 1 (M15 globular cluster), night 2026-11-10 16:54 - 05:14 UTC:")
        and ": planned 2026-11-10 " in out
    )
    # The flats need the twilight; a night with the Sun below -12 degrees has none.
    assert main(["tasks", "why", "2", "--night", "2026-11-10"]) == 0
    assert "not planned: its windows lie outside the night" in capsys.readouterr().out
    assert main(["tasks", "why", "2", "--night", "2026-11-10", "--max-sun-altitude", "-3"]) == 0
    assert ": planned 2026-11-1" in capsys.readouterr().out
    # A night long after its windows.
    assert main(["tasks", "why", "1", "--night", "2026-12-24", "--site", str(SITE_FILE)]) == 0
    assert "not planned: its windows lie outside the night" in capsys.readouterr().out
    assert main(["tasks", "cancel", "1"]) == 0
    capsys.readouterr()
    assert main(["tasks", "why", "1", "--night", "2026-11-10"]) == 0
    assert (
        capsys.readouterr()
        .out.strip()
        .endswith("not planned: it is CANCELED (canceled from the command line)")
    )


def test_why_without_a_site_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["tasks", "add", _sample("m15-globular-cluster")]) == 0
    capsys.readouterr()
    assert main(["tasks", "why", "1"]) == 2  # a configuration error
    assert capsys.readouterr().err.splitlines() == [
        "nightcrew: error: no site: give --site FILE or set NIGHTCREW_SITE"
        " (none of site.yaml, shared/site.yaml here)"
    ]


def test_schema_prints_the_models_json_schema(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["tasks", "schema"]) == 0
    assert json.loads(capsys.readouterr().out) == request_group_schema()


async def test_a_task_added_reaches_the_scheduler_by_its_event_within_2_clock_seconds(tmp_path: Path) -> None:
    """What ``tasks add --comm`` does after storing: the scheduler re-plans at once, not at its poll."""
    epoch = datetime(2026, 11, 10, 19, 0, tzinfo=UTC)
    path = tmp_path / DEFAULT_TASKS_DB
    async with (
        Observatory(epoch=epoch) as obs,
        SqliteTaskArchive(path, clock=obs.clock, poll_interval=0) as archive,
    ):
        # The archive does not poll; the scheduler polls once an hour: only the event can be quick.
        scheduler = await obs.start(
            SchedulerModule,
            "scheduler",
            archive=archive,
            store=archive,
            time_limit_s=2.0,
            poll_interval_s=3600.0,
        )
        await obs.wait_for(lambda: scheduler.schedule is not None, 60.0)
        async with SqliteTaskArchive(path, poll_interval=0) as cli_archive:  # as `nightcrew tasks add`
            (task,) = await cli_archive.add_request_group(load_samples()["m15-globular-cluster"])
        added = obs.clock.now()
        await announce_change(obs.comm("operator"), [task.id], "added")

        async def planned() -> bool:
            plan = await scheduler.get_plan()
            return plan is not None and task.id in {slot.task_id for slot in plan.slots}

        waited = await obs.wait_for(planned, 60.0, message="the new task was not planned")
        plan = await scheduler.get_plan()
        assert plan is not None
        reaction = (plan.planned_at - added).total_seconds()
        print(
            f"\ntasks add -> re-planned with it: {reaction:.2f} clock s"
            f" (plan ready after {waited:.1f} clock s)"
        )
        assert reaction <= 2.0
