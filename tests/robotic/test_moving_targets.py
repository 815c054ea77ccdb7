"""Moving targets in the request format (docs/tasks.md's section, run as written) and the scheduler."""

from __future__ import annotations

import re
import shlex
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import pytest
import yaml

from nightcrew.astro import separation
from nightcrew.cli.main import main
from nightcrew.robotic.scheduler import SkyGrid, TimeGrid
from nightcrew.robotic.scheduler.moving import EphemerisTarget
from nightcrew.robotic.tasks import (
    InvalidTaskError,
    MajorBodyTarget,
    MpcElementsTarget,
    OrbitalElementsTarget,
    SatelliteTarget,
    parse_request_group,
    tasks_of_group,
)
from nightcrew.robotic.tasks.blocks import block_of
from nightcrew.site import Site

ROOT = Path(__file__).parents[2]
DOC = (ROOT / "docs/tasks.md").read_text()
SECTION = DOC.split("## Moving targets", 1)[1].split("\n## ", 1)[0]
EXAMPLE_YAML = re.search(r"```yaml\n(.*?)```", SECTION, flags=re.S).group(1)  # type: ignore[union-attr]
EXAMPLE_SH = re.search(r"```sh\n(.*?)```", SECTION, flags=re.S).group(1)  # type: ignore[union-attr]
SITE = Site(latitude=51.56, longitude=9.94, elevation=201.0)


def example() -> dict[str, Any]:
    data = yaml.safe_load(EXAMPLE_YAML)
    assert isinstance(data, dict)
    return data


def problems(data: dict[str, Any]) -> list[str]:
    with pytest.raises(InvalidTaskError) as caught:
        parse_request_group(data)
    return [str(problem) for problem in caught.value.problems]


def test_the_example_holds_one_target_of_each_kind() -> None:
    group = parse_request_group(example())
    kinds = [type(r.configurations[0].target) for r in group.requests]
    assert kinds == [MpcElementsTarget, OrbitalElementsTarget, MajorBodyTarget, SatelliteTarget]
    assert group.requests[0].configurations[0].target.name == "(example) 2026 XA"  # type: ignore[union-attr]


def test_the_section_runs_as_written(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    for name in ("NIGHTCREW_TASKS_DB", "NIGHTCREW_COMM", "NIGHTCREW_SITE"):
        monkeypatch.delenv(name, raising=False)
    (tmp_path / "site.yaml").write_text((ROOT / "examples/sim/shared/site.yaml").read_text())
    (tmp_path / "moving.yaml").write_text(EXAMPLE_YAML)
    outputs = []
    for line in EXAMPLE_SH.splitlines():
        words = shlex.split(line, comments=True)
        assert main(words[1:]) == 0, line
        outputs.append(capsys.readouterr().out)
    assert "tasks 1, 2, 3, 4" in outputs[0]
    assert re.search(r"task 1 .*: planned 2026-11-10 ", outputs[1])
    assert re.search(r"task 4 .*: planned 2026-11-10 18:", outputs[2])  # the pass at 18:38


def test_a_bad_tle_checksum_is_one_line_naming_file_and_field(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("NIGHTCREW_COMM", raising=False)
    (tmp_path / "moving.yaml").write_text(EXAMPLE_YAML.replace("15.49815350868470", "15.49815350868471"))
    assert main(["tasks", "add", "moving.yaml"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "nightcrew: error: moving.yaml: invalid request group: requests[3].configurations[0].target"
        ".tle_line2: checksum is '1', the line's digits give 0; nothing was stored"
    ]
    assert not (tmp_path / "tasks.sqlite").exists()


def test_elements_are_checked_by_their_scheme() -> None:
    data = example()
    comet = data["requests"][1]["configurations"][0]["target"]
    comet["scheme"] = "MPC_MINOR_PLANET"
    assert problems(data) == [
        "requests[1].configurations[0].target.meandist: required for the MPC_MINOR_PLANET scheme",
        "requests[1].configurations[0].target.meananom: required for the MPC_MINOR_PLANET scheme",
        "requests[1].configurations[0].target.perihdist: not used by the MPC_MINOR_PLANET scheme",
        "requests[1].configurations[0].target.epochofperih: not used by the MPC_MINOR_PLANET scheme",
    ]
    for name in ("perihdist", "epochofperih"):
        del comet[name]
    comet.update(meandist=2.0, meananom=10.0, eccentricity=1.0)
    assert problems(data) == [
        "requests[1].configurations[0].target.eccentricity: must be >= 0 and < 1 for elliptical elements,"
        " got 1.0"
    ]


def test_elements_far_from_the_windows_are_refused() -> None:
    data = example()
    data["requests"][1]["configurations"][0]["target"]["epochofel"] = 60000.0
    assert problems(data) == [
        "requests[1].configurations[0].target.epochofel: the elements' epoch is 1355 days from the"
        " request's windows (at most 200 days): give elements for an epoch near the night"
    ]
    data = example()
    data["requests"][3]["windows"] = [{"start": "2026-12-10T18:30:00Z", "end": "2026-12-10T18:50:00Z"}]
    first = problems(data)[0]
    assert first.startswith("requests[3].configurations[0].target.tle_line1: the elements' epoch is 30")


def test_an_unknown_kind_or_body_is_named() -> None:
    data = example()
    data["requests"][2]["configurations"][0]["target"] = {"type": "PLANET", "name": "jupiter"}
    assert problems(data) == [
        "requests[2].configurations[0].target.type: must be one of ORBITAL_ELEMENTS, MPC_ELEMENTS,"
        " MAJOR_BODY, SATELLITE (absent: sidereal), got PLANET"
    ]
    data["requests"][2]["configurations"][0]["target"] = {"type": "MAJOR_BODY", "name": "vulcan"}
    assert problems(data)[0].startswith("requests[2].configurations[0].target.name: must be one of mercury,")


def test_the_scheduler_follows_a_body_along_its_ephemeris() -> None:
    group = parse_request_group(example())
    tasks = tasks_of_group(group, "g", ["1", "2", "3", "4"])
    assert block_of(tasks[2]) is None  # no site: a moving target has no position
    block = block_of(tasks[2], site=SITE)  # Jupiter
    assert block is not None and isinstance(block.target, EphemerisTarget)
    start = datetime(2026, 11, 10, 17, 0, tzinfo=UTC).timestamp()
    sky = SkyGrid(TimeGrid(start, 3600.0, 12), SITE, [block])
    # Jupiter rises near 22:45 UTC and is at about 52° at 06:00 (DE421, skyfield).
    assert sky.altitude[0, 0] < -20 and sky.altitude[0, -1] > 45
    track = block.target.track(sky.edges)
    assert list(sky.moon_distance()[0]) == pytest.approx(
        list(separation(track.ra, track.dec, sky.moon_ra, sky.moon_dec))
    )


def test_a_satellite_pass_counts_in_the_slice_it_rises_in() -> None:
    group = parse_request_group(example())
    block = block_of(tasks_of_group(group, "g", ["1", "2", "3", "4"])[3], site=SITE)
    assert block is not None and isinstance(block.target, EphemerisTarget)
    start = datetime(2026, 11, 10, 18, 14, tzinfo=UTC).timestamp()
    sky = SkyGrid(TimeGrid(start, 300.0, 12), SITE, [block])
    # The pass rises above the horizon at about 18:34 and culminates near 68° at 18:39.
    high = [index for index, alt in enumerate(sky.altitude[0]) if alt > 30]
    assert high == [4, 5]  # the edges of the slice 18:34 - 18:39
    assert 60 < sky.altitude[0, 4] < 75
    ra, dec = block.target.position_at(start)
    assert (ra, dec) != (0.0, 0.0) and -90 < dec < 90
