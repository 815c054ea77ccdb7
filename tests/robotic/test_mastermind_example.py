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
        ("focus_field.magnitudes", {"magnitudes": [10, 6]}, r"must be \[bright, faint\], got \(10.0, 6.0\)"),
        ("focus_field.min_altitude", {"min_altitude": 95}, r"must be within \[0, 90\) degrees, got 95"),
        ("focus_field", {"height": 5}, r"unknown keys \['height'\]"),
        ("focus_field.magnitudes", {"magnitudes": [11, 14]}, r"the catalogue holds stars to G 10"),
        ("focus_temperature", {"module": "telescope"}, r"give exactly one of 'sensor'"),
        ("focus_attempts", 0, r"must be an integer >= 1, got 0"),
        ("focus_retry_interval", 0, r"0 is out of range \(must be >= 0.01 s\)"),
    ],
)
def test_bad_focus_options_are_refused_naming_the_key(
    tmp_path: Path, key: str, value: object, message: str
) -> None:
    config = load_config(EXAMPLE, environ={"NIGHTCREW_TASKS_DB": str(tmp_path / "tasks.sqlite")})
    with pytest.raises(ConfigError, match=rf"key '{key}': {message}"):
        build_object({**config, "name": "mastermind", key.split(".")[0]: value}, Module)
