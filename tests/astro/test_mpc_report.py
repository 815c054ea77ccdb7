"""MPC 80-column observation lines (nightcrew.astro.mpc_report)."""

from __future__ import annotations

from datetime import UTC, datetime

import pytest

from nightcrew.astro.mpc_report import mpc_observation_line

WHEN = datetime(2026, 11, 10, 22, 0, tzinfo=UTC).timestamp()


def test_a_line_puts_each_field_in_its_columns() -> None:
    line = mpc_observation_line(
        unix_time=WHEN,
        ra=58.47412,
        dec=26.8643,
        observatory_code="500",
        designation="K26X00A",
        magnitude=15.2,
        band="R",
    )
    assert len(line) == 80
    assert line[5:12] == "K26X00A" and line[14] == "C"
    assert line[15:32] == "2026 11 10.916667"
    assert line[32:44] == "03 53 53.789"
    assert line[44:56] == "+26 51 51.48"
    assert line[65:71] == "15.2 R" and line[77:80] == "500"


def test_rounding_carries_into_the_next_day_and_negative_declinations_keep_their_sign() -> None:
    just_before_midnight = datetime(2026, 11, 30, 23, 59, 59, 990000, tzinfo=UTC).timestamp()
    line = mpc_observation_line(
        unix_time=just_before_midnight, ra=359.99999999, dec=-0.5, observatory_code="G96", number="00433"
    )
    assert line[:5] == "00433"
    assert line[15:32] == "2026 12 01.000000"
    assert line[32:44] == "00 00 00.000"
    assert line[44:56] == "-00 30 00.00"


def test_fields_that_do_not_fit_are_refused_naming_them() -> None:
    with pytest.raises(ValueError, match=r"^designation: at most 7 characters"):
        mpc_observation_line(unix_time=WHEN, ra=1.0, dec=1.0, observatory_code="500", designation="2026 XA12")
    with pytest.raises(ValueError, match=r"^observatory_code: three characters"):
        mpc_observation_line(unix_time=WHEN, ra=1.0, dec=1.0, observatory_code="5000", designation="K26X00A")
