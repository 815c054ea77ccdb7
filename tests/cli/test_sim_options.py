"""``nightcrew sim`` parses its arguments into SimOptions and nothing else (the night is built in
nightcrew.night from the options)."""

from __future__ import annotations

import argparse
import shutil
from datetime import date, time
from pathlib import Path

import pytest

from nightcrew.cli import sim
from nightcrew.cli.main import main
from nightcrew.night.build import bundled_observatory
from nightcrew.night.options import SimOptions


def _parsed(*argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    parser.add_argument("--debug", action="store_true")
    sim.add_parser(parser.add_subparsers())
    return parser.parse_args(["sim", *argv])


def test_the_defaults_are_the_options_defaults() -> None:
    assert sim.sim_options(_parsed()) == SimOptions()


def test_every_argument_lands_in_its_option() -> None:
    argv = "--out night --date 2026-12-01 --seed 7 --weather clear --start 19:30 --hours 2 --quick"
    argv += " --targets 2 --filters B --exposure-time 5 --calibration-frames 0 --configs mine"
    argv += " --indi 7624 --console --archive -v --speed 60"
    options = sim.sim_options(_parsed(*argv.split()))
    assert options == SimOptions(
        out=Path("night"),
        date=date(2026, 12, 1),
        speed=60.0,
        seed=7,
        weather="clear",
        start=time(19, 30),
        hours=2.0,
        quick=True,
        targets=2,
        filters="B",
        exposure_time=5.0,
        calibration_frames=0,
        configs=Path("mine"),
        indi=7624,
        console=37180,
        archive=True,
        show_logs=True,
    )


def test_a_directory_whose_scheduler_names_another_archive_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    observatory = tmp_path / "observatory"
    shutil.copytree(bundled_observatory(), observatory)
    scheduler = observatory / "robotic" / "scheduler.yaml"
    scheduler.write_text(
        scheduler.read_text(encoding="utf-8").replace("${OBSERVATORY_DATA:-..}/tasks.sqlite", "tasks.sqlite"),
        encoding="utf-8",
    )
    out = tmp_path / "night"
    assert main(["sim", "--quick", "--configs", str(observatory), "--out", str(out)]) == 2
    error = capsys.readouterr().err
    assert error.count("\n") == 1, error
    assert f"the scheduler's task archive is {observatory}/robotic/tasks.sqlite, not the night's" in error
    assert "(path: ${OBSERVATORY_DATA}/tasks.sqlite)" in error
