"""File names made from FITS headers: patterns are checked, values cannot leave the directory."""

from __future__ import annotations

import pytest

from nightcrew.errors import ConfigError
from nightcrew.interfaces import FitsValue
from nightcrew.vfs.filenames import check_filename_pattern, format_filename


def test_filename_pattern_is_checked_and_values_cannot_escape() -> None:
    with pytest.raises(ConfigError, match="must be an absolute VFS file path"):
        check_filename_pattern("cache/{DATE-OBS}.fits")
    with pytest.raises(ConfigError, match=r"placeholder \{date\} .* is not a FITS keyword"):
        check_filename_pattern("/cache/{date}.fits")
    header: dict[str, FitsValue] = {"OBJECT": "../../etc/passwd", "FILTER": "..", "FOCUS": 25.123456}
    assert format_filename("/cache/{OBJECT}-{FILTER}-{FOCUS:.2f}-{MISSING}.fits", header) == (
        "/cache/etc-passwd-_-25.12-none.fits"
    )
