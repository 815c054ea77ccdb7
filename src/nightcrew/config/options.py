"""Building a frozen dataclass of options from a mapping in a YAML file, naming an unknown key."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, TypeVar

__all__ = ["dataclass_from_options"]

T = TypeVar("T")


def dataclass_from_options(cls: type[T], options: Mapping[str, Any]) -> T:
    """``cls(**options)``; ValueError starting with the first unknown key and listing the known ones
    (the dataclass's own checks raise theirs)."""
    known = {field.name for field in dataclasses.fields(cls)}  # type: ignore[arg-type]
    unknown = sorted(set(options) - known)
    if unknown:
        raise ValueError(f"{unknown[0]} is not an option; known: {', '.join(sorted(known))}")
    return cls(**options)
