"""Counting errors against limits (pure bookkeeping)."""

from __future__ import annotations

import pytest

from nightcrew.error_limits import ErrorLimit, ErrorLimits
from nightcrew.errors import InitError, MotionError, MoveError


def test_limit_counts_subclasses_within_the_timespan() -> None:
    limits = ErrorLimits()
    limit = ErrorLimit(MotionError, 3, timespan=100)
    limits.register(limit)
    assert limits.record(MoveError("a"), now=0) == []
    assert limits.record(InitError("b"), now=50) == []
    assert limits.record(MoveError("c"), now=120) == []  # the first fell out of the window
    assert limits.record(MoveError("d"), now=140) == [limit]
    assert limits.record(MoveError("e"), now=141) == []  # counting restarts after escalation


def test_limit_for_one_remote_module_ignores_others() -> None:
    limits = ErrorLimits()
    limit = ErrorLimit(MoveError, 1, module="telescope")
    limits.register(limit)
    assert limits.record(MoveError("x", module="dome"), now=0) == []
    assert limits.record(MoveError("x"), now=0) == []
    assert limits.record(MoveError("x", module="telescope"), now=0) == [limit]


def test_other_error_types_do_not_count() -> None:
    limits = ErrorLimits()
    limits.register(ErrorLimit(MoveError, 1))
    assert limits.record(ValueError("x"), now=0) == []


def test_limit_must_be_positive() -> None:
    with pytest.raises(ValueError, match="error limit must be >= 1"):
        ErrorLimits().register(ErrorLimit(MoveError, 0))
