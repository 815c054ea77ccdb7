"""SEP's bare exceptions become one ImageDataError that names the cause, not SEP's tuning advice."""

from __future__ import annotations

from nightcrew.images.errors import ImageDataError
from nightcrew.images.processors.detection._sep import _detection_error


def test_a_deblending_overflow_names_the_bright_or_crowded_field() -> None:
    raw = Exception(
        "object deblending overflow: Limit of 1024 sub-objects reached while deblending. Increase it "
        "with sep.set_sub_object_limit()."
    )
    error = _detection_error(raw)
    assert isinstance(error, ImageDataError)
    assert "a very bright star or a crowded field" in str(error)
    assert "set_sub_object_limit" not in str(error)


def test_other_sep_errors_keep_their_first_line() -> None:
    error = _detection_error(Exception("internal pixel buffer full\nsecond line"))
    assert str(error) == "source detection failed: internal pixel buffer full"
