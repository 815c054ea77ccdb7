"""examples/robotic/mastermind.yaml is a valid configuration that builds a Mastermind."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.errors import ConfigError
from nightcrew.modules import Module
from nightcrew.modules.robotic import Mastermind
from nightcrew.robotic.scripts import ImagingScript

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "robotic" / "mastermind.yaml"


def test_the_example_validates_and_builds(tmp_path: Path) -> None:
    config = load_config(EXAMPLE, environ={"NIGHTCREW_TASKS_DB": str(tmp_path / "tasks.sqlite")})
    validate_config(config, Module)
    mastermind = build_object({**config, "name": "mastermind"}, Module)
    assert isinstance(mastermind, Mastermind)
    assert isinstance(mastermind._runner.scripts["EXPOSE"], ImagingScript)
    assert not (tmp_path / "tasks.sqlite").exists()  # constructors do no I/O


def test_a_mastermind_without_site_or_schedule_is_refused(tmp_path: Path) -> None:
    config = load_config(EXAMPLE, environ={"NIGHTCREW_TASKS_DB": str(tmp_path / "tasks.sqlite")})
    without_site = {key: value for key, value in config.items() if key != "site"}
    with pytest.raises(ConfigError, match=r"key 'site': the mastermind needs the observatory's site"):
        build_object({**without_site, "name": "mastermind"}, Module)
    with pytest.raises(ConfigError, match=r"key 'poll_interval': 0 is out of range \(must be >= 0.01 s\)"):
        build_object({**config, "name": "mastermind", "poll_interval": 0}, Module)


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("focus_altitude", 0, r"must be within \(0, 90\] degrees, got 0"),
        ("focus_altitude", 91, r"91 is out of range \(must be <= 90.0 deg\)"),
        ("focus_azimuth", 360, r"must be within \[0, 360\) degrees, got 360"),
        ("focus_retry_interval", 0, r"0 is out of range \(must be >= 0.01 s\)"),
    ],
)
def test_bad_focus_options_are_refused_naming_the_key(
    tmp_path: Path, key: str, value: float, message: str
) -> None:
    config = load_config(EXAMPLE, environ={"NIGHTCREW_TASKS_DB": str(tmp_path / "tasks.sqlite")})
    with pytest.raises(ConfigError, match=rf"key '{key}': {message}"):
        build_object({**config, "name": "mastermind", key: value}, Module)
