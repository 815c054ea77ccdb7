"""The helpers that judge and sample type hints catch what they should."""

from __future__ import annotations

import enum
import re
from dataclasses import dataclass
from datetime import datetime
from typing import Any, Literal

import pytest

from nightcrew.interfaces import Binning, MotionStatus

from .wire_types import hint_problems, sample_values


class _FloatEnum(enum.Enum):
    HALF = 0.5


@dataclass(frozen=True)
class _BadResult:
    ok: int
    bad: set[int]


@pytest.mark.parametrize(
    "hint",
    [
        Any,
        None,
        bytes,
        datetime,
        MotionStatus,
        Binning,
        list[int],
        tuple[float, float],
        tuple[str, ...],
        dict[str, tuple[bool, bool, bool]],
        str | None,
        Literal["a", 1],
        list[Binning] | None,
    ],
    ids=str,
)
def test_accepted_hints(hint: Any) -> None:
    assert hint_problems(hint) == []


@pytest.mark.parametrize(
    ("hint", "message"),
    [
        (set[int], "cannot travel"),
        (dict[int, str], "dict keys must be str"),
        (list, "bare list"),
        (object, "object cannot travel"),
        (complex, "complex cannot travel"),
        (list[complex] | None, "complex cannot travel"),
        (_FloatEnum, "not str/int-valued"),
        (_BadResult, r"hint\.bad"),
        (Literal[1.5], "Literal values"),
    ],
    ids=str,
)
def test_refused_hints(hint: Any, message: str) -> None:
    problems = hint_problems(hint)
    assert len(problems) == 1
    assert re.search(message, problems[0]), problems


def test_union_samples_cover_every_member() -> None:
    kinds = {type(v) for v in sample_values(int | str | None)}
    assert kinds == {int, str, type(None)}


def test_dataclass_samples_vary_every_field() -> None:
    samples = sample_values(Binning)
    assert len({s.x for s in samples}) > 1
    assert all(isinstance(s, Binning) for s in samples)
