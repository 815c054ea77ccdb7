"""Bounds declared in type hints (nightcrew.interfaces.quantities), as the validator reads them."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from nightcrew.cli.main import main
from nightcrew.config import check_value
from nightcrew.interfaces.quantities import Altitude, ExposureTime, Period, PeriodOrOff, TimeZoneName


def _problem(value: object, hint: Any) -> str | None:
    problem = next(check_value(value, hint, "key", None), None)
    return None if problem is None else problem.message


@pytest.mark.parametrize(
    ("value", "hint", "message"),
    [
        (10.0, Period, None),
        (1e-320, Period, "1e-320 is out of range (must be >= 0.01 s)"),
        (90, Altitude, None),
        (200, Altitude, "200 is out of range (must be <= 90.0 deg)"),
        (1e308, ExposureTime | None, "1e+308 is out of range (must be <= 86400.0 s)"),
        (None, ExposureTime | None, None),
        ("x", ExposureTime | None, "expected float | None, got str 'x'"),
        (0, PeriodOrOff, None),
        (1e-320, PeriodOrOff, "1e-320 is not 0 (off) or a period of 0.01..86400 s"),
        ("Europe/Berlin", TimeZoneName, None),
        (
            "Mars/Olympus",
            TimeZoneName,
            "'Mars/Olympus' is not an IANA time zone name such as 'Europe/Berlin'",
        ),
        (
            10**400,
            float,
            "expected a finite number, got 1000000000000000000000000000000000000... (401 characters)",
        ),
        (2**63, int, "expected an integer of at most 64 bits, got 9223372036854775808"),
        (2**63 - 1, int, None),
    ],
)
def test_declared_bounds(value: object, hint: Any, message: str | None) -> None:
    assert _problem(value, hint) == message


def test_a_site_out_of_bounds_is_one_line_naming_the_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("x.yaml").write_text(
        "class: nightcrew.modules.test.StandAlone\nsite: {latitude: 10, longitude: 10, elevation: 1e308}\n"
    )
    assert main(["check", "x.yaml"]) == 2
    assert (
        capsys.readouterr().err
        == "x.yaml:2: key 'site': elevation must be within -500..9000 metres, got 1e+308\n"
    )
