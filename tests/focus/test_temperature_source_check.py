"""``nightcrew check`` refuses a refocus temperature source that no module of the observatory provides."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.night.build import bundled_observatory


@pytest.mark.usefixtures("bundled_xmpp_files")
def test_check_refuses_a_focus_temperature_no_module_provides(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    observatory = tmp_path / "observatory"
    ignore = shutil.ignore_patterns("frames", "xmpp", "logs", "*.sqlite*", "*.jsonl")
    shutil.copytree(bundled_observatory(), observatory, ignore=ignore)
    mastermind = observatory / "robotic" / "mastermind.yaml"
    weather = observatory / "robotic" / "weather.yaml"
    files = [str(mastermind), str(observatory / "focuser.yaml"), str(weather)]
    text = mastermind.read_text(encoding="utf-8")

    def check_with(source: str) -> tuple[int, str]:
        mastermind.write_text(text + f"focus_temperature: {source}\n", encoding="utf-8")
        capsys.readouterr()
        return main(["check", *files]), capsys.readouterr().err

    assert check_with("{module: focuser, sensor: ambient}") == (0, "")  # the sim focuser's thermometer
    code, error = check_with("{module: thermometer, sensor: temperature}")
    assert code == 2
    assert "mastermind.yaml: key 'focus_temperature': no module 'thermometer' here provides" in error
    code, error = check_with("{module: focuser, weather_sensor: temperature}")
    assert code == 2
    assert "module 'focuser' (" in error and "has no IWeather, so no 'weather_sensor' to read" in error


@pytest.mark.usefixtures("bundled_xmpp_files")
def test_check_refuses_an_imaging_scripts_focus_temperature_no_module_provides(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The imaging script's refocus trigger names its temperature the same way, nested in the runner."""
    observatory = tmp_path / "observatory"
    ignore = shutil.ignore_patterns("frames", "xmpp", "logs", "*.sqlite*", "*.jsonl")
    shutil.copytree(bundled_observatory(), observatory, ignore=ignore)
    mastermind = observatory / "robotic" / "mastermind.yaml"
    exposing = "EXPOSE: {class: nightcrew.robotic.scripts.ImagingScript, "
    text = mastermind.read_text(encoding="utf-8")
    assert exposing in text
    trigger = (
        "refocus_triggers: {temperature_change: 1.0}, focus_temperature: {module: thermometer, sensor: t}, "
    )
    mastermind.write_text(text.replace(exposing, exposing + trigger, 1), encoding="utf-8")
    files = [
        str(mastermind),
        str(observatory / "focuser.yaml"),
        str(observatory / "robotic" / "weather.yaml"),
    ]
    assert main(["check", *files]) == 2
    error = capsys.readouterr().err
    assert "key 'runner.scripts.EXPOSE.focus_temperature': no module 'thermometer' here provides" in error
