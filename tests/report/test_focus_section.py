"""The report's focus section: each recorded series with its best focus, or why it found none."""

from __future__ import annotations

import math
from datetime import UTC, datetime
from typing import Any

from nightcrew.report import Night, Record
from nightcrew.report._sections import focus_section
from nightcrew.report.records import FOCUS_SERIES

#: 16:50 UTC on the sample night: the dusk focus.
T0 = datetime(2026, 11, 10, 16, 50, tzinfo=UTC).timestamp()
POSITIONS = [24.1, 24.4, 24.7, 25.0, 25.3, 25.6, 25.9]


def _series(t: float, widths: list[float], **status: Any) -> Record:
    """A FocusSeries line as the recorder writes it: the focus module's auto_focus_status()."""
    measurements = [[p, w] for p, w in zip(POSITIONS, widths, strict=True)]
    data = {"running": False, "count": 7, "step": 0.3, "done": 7, "measurements": measurements, **status}
    return Record(T0 + t, FOCUS_SERIES, "focus", data)


def test_a_failed_series_shows_why_and_a_found_one_its_focus_and_fit() -> None:
    v_shape = [math.hypot(2.0, 10.0 * (p - 25.0)) for p in POSITIONS]
    garbage = [3.1, 2.2, math.nan, 2.9, 2.4, 3.0, 2.6]
    reason = "the widths do not form a clear V"
    night = Night(
        records=[
            _series(0, garbage, failed=reason),
            _series(1800, v_shape, focus=25.0012, error=0.0081),
        ]
    )

    failed_part, found_part = focus_section(night).split("</svg>")[:2]

    assert f"16:50: focus series failed: {reason}" in failed_part
    assert "nan" not in failed_part and "best focus" not in failed_part
    assert "hyperbola fit" not in failed_part  # the fit was refused: none is drawn
    assert "17:20: best focus 25.001 ± 0.008 mm</p>" in found_part
    assert "hyperbola fit" in found_part
