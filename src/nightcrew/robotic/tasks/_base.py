"""What every part of the task model shares: the base class, strict value types and field errors.

Models are pydantic v2 classes, frozen and closed (an unknown key is an error, so a typo such as
``exposure_tme`` is caught instead of ignored). Numbers are strict: ``"30"`` or ``true`` is not an
exposure time. Rules that relate several fields raise :class:`FieldError` with the paths of the
fields at fault *relative to the model that checks them*; :mod:`._validation` appends it to pydantic's
location, so the final message names the exact field.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from datetime import UTC, datetime
from typing import Annotated, Any

from pydantic import AfterValidator, AllowInfNan, BaseModel, ConfigDict, Strict

__all__ = ["ExtraParams", "FieldError", "Integer", "Number", "TaskModel", "UtcDatetime", "raise_problems"]


class TaskModel(BaseModel):
    """Base of all task model classes: immutable, no unknown keys, validated when built."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class FieldError(ValueError):
    """Rules broken by fields of one model.

    Args:
        problems: ``(path, message)`` pairs; ``path`` is relative to the model that raises
            (``target``, ``instrument_configs[0].exposure_time``).
    """

    def __init__(self, problems: Sequence[tuple[str, str]]) -> None:
        super().__init__("; ".join(f"{path}: {message}" for path, message in problems))
        self.problems = tuple(problems)


def raise_problems(problems: Iterable[tuple[str, str]]) -> None:
    """Raise :class:`FieldError` with ``problems`` if there are any (for ``model_validator``)."""
    found = list(problems)
    if found:
        raise FieldError(found)


def _as_utc(value: datetime) -> datetime:
    # A time without a zone is read as UTC (YAML timestamps without offset are); others are converted.
    if value.tzinfo is None:
        return value.replace(tzinfo=UTC)
    return value.astimezone(UTC)


#: A date and time, always aware and in UTC.
UtcDatetime = Annotated[datetime, AfterValidator(_as_utc)]
#: A real number: an int or a float, not a string or a bool, and finite (``.inf`` is no priority).
Number = Annotated[float, Strict(), AllowInfNan(False)]
#: A whole number (not a bool, not a float).
Integer = Annotated[int, Strict()]
#: Free parameters for the scripts that run a configuration.
ExtraParams = dict[str, Any]
