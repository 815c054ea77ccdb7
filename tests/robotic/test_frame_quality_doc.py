"""docs/observatory.md, "Frame quality": its mastermind keys build the scripts and pass ``check``."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from nightcrew.cli.main import main
from nightcrew.config import build_object
from nightcrew.errors import ConfigError
from nightcrew.robotic.runner import TaskRunner
from nightcrew.robotic.scripts import ImagingScript

DOC = (Path(__file__).parents[2] / "docs/observatory.md").read_text(encoding="utf-8")


def _block() -> str:
    section = DOC.split("## Frame quality", 1)[1]
    match = re.search(r"^```yaml\n(.*?)^```", section, flags=re.M | re.S)
    assert match is not None, "no yaml block in docs/observatory.md, Frame quality"
    return match.group(1)


def test_the_documented_options_build_imaging_scripts_that_grade_and_refocus() -> None:
    runner = build_object(yaml.safe_load(_block())["runner"])
    assert isinstance(runner, TaskRunner) and set(runner.scripts) == {"EXPOSE", "REPEAT_EXPOSE"}
    for script in runner.scripts.values():
        assert isinstance(script, ImagingScript)


def test_the_documented_keys_in_the_bundled_mastermind_pass_check(
    observatory_copy: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mastermind = observatory_copy / "robotic" / "mastermind.yaml"
    text = mastermind.read_text(encoding="utf-8")
    start, end = text.index("runner:\n"), text.index("\n\n", text.index("runner:\n"))
    mastermind.write_text(text[:start] + _block() + text[end:], encoding="utf-8")
    assert main(["check", str(mastermind)]) == 0, capsys.readouterr().err


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"grading": {"max_retakes": -1}}, r"key 'grading.max_retakes': max_retakes must be an integer >= 0"),
        (
            {"refocus_triggers": {"hfr_rise": 0.2}},
            r"key 'refocus_triggers.hfr_rise': hfr_rise is not an option; known: count, ",
        ),
        (
            {"grading": {}, "refocus_triggers": {"fwhm_rise": -1}},
            r"key 'refocus_triggers.fwhm_rise': fwhm_rise must be >= 0",
        ),
        ({"filter_focus_offsets": {"R": 0.1}}, r"key 'focuser': filter focus offsets need the focuser"),
        (
            {"refocus_triggers": {"temperature_change": 1.0}},
            r"key 'refocus_triggers.temperature_change': temperature_change needs the script's "
            r"focus_temperature",
        ),
        (
            {"refocus_triggers": {"fwhm_rise": 0.2}},
            r"key 'refocus_triggers.fwhm_rise': a FWHM rise is measured",
        ),
        (
            {"focus_temperature": {"module": "weather"}},
            r"key 'focus_temperature': give exactly one of 'sensor' \(ITemperatures\) or 'weather_sensor'",
        ),
    ],
)
def test_options_that_make_no_sense_are_config_errors(options: dict[str, object], message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        ImagingScript(**options)  # type: ignore[arg-type]
