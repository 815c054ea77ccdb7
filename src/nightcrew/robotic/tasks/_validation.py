"""Turning plain data (from YAML, JSON or an API) into a :class:`RequestGroup`, or into problems.

Every problem names the field by its full path (``requests[0].configurations[1]
.instrument_configs[0].exposure_time: must be > 0``): pydantic's location for type and range
errors, extended by the relative paths that :class:`~._base.FieldError` carries for the rules
between fields. Nothing is built unless everything is valid.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping, Sequence
from typing import Any

from pydantic import BaseModel, ValidationError
from pydantic_core import ErrorDetails

from nightcrew.config import load_data_file
from nightcrew.errors import ConfigError
from nightcrew.robotic.tasks._base import FieldError
from nightcrew.robotic.tasks._errors import InvalidTaskError, TaskProblem
from nightcrew.robotic.tasks._moving import TARGET_KINDS
from nightcrew.robotic.tasks._request import RequestGroup

__all__ = [
    "filled_defaults",
    "load_request_group_file",
    "parse_request_group",
    "problems_of",
    "request_group_schema",
]


def request_group_schema() -> dict[str, Any]:
    """The request format as JSON Schema (draft 2020-12), from the model the validator uses, so
    a form, a client or a document built from it cannot drift from what is accepted."""
    return RequestGroup.model_json_schema()


def filled_defaults(model: BaseModel, prefix: str = "") -> list[tuple[str, object]]:
    """``(path, value)`` of every field the validator filled in with its default (the file did not
    give it), in the model's order; values as JSON would give them (``min_lunar_distance: 30``)."""
    found: list[tuple[str, object]] = []
    dumped = model.model_dump(mode="json")
    for name in type(model).model_fields:
        path = _join(prefix, name)
        value = getattr(model, name)
        if isinstance(value, BaseModel):
            found += filled_defaults(value, path)
        elif isinstance(value, tuple | list) and value and all(isinstance(v, BaseModel) for v in value):
            for index, item in enumerate(value):
                found += filled_defaults(item, f"{path}[{index}]")
        elif name not in model.model_fields_set:
            found.append((path, dumped[name]))
    return found


def parse_request_group(data: object, *, prefix: str = "", source: str = "") -> RequestGroup:
    """Validate ``data`` (a mapping as in a request group file) and build the group.

    Args:
        data: The plain data.
        prefix: Path of ``data`` inside a larger document (``request_groups[2]``), for messages.
        source: File or URL it came from, for messages.

    Raises:
        InvalidTaskError: Naming every problem with its field path.
    """
    if not isinstance(data, Mapping):
        raise InvalidTaskError(
            [TaskProblem(prefix, f"expected a mapping, got {_describe(data)}")], source=source
        )
    try:
        return RequestGroup.model_validate(data)
    except ValidationError as exc:
        raise InvalidTaskError(list(problems_of(exc, prefix=prefix)), source=source) from None


def load_request_group_file(path: str | os.PathLike[str]) -> RequestGroup:
    """Read and validate one request group from a YAML or JSON file.

    Raises:
        InvalidTaskError: The file cannot be read or parsed, or the group is invalid.
    """
    source = os.fspath(path)
    try:
        data = load_data_file(path)  # size, depth, alias, encoding and date limits: one loader
    except ConfigError as exc:
        where = f"line {exc.line}: " if exc.line else ""
        raise InvalidTaskError([TaskProblem("", where + exc.message)], source=source) from None
    return parse_request_group(data, source=source)


def problems_of(exc: ValidationError, *, prefix: str = "") -> Iterator[TaskProblem]:
    """The problems in pydantic's ``exc``, with full paths and plain messages."""
    errors = exc.errors(include_url=False)
    for error in errors:
        if error["type"] == "too_short" and _has_inner_errors(error, errors):
            continue  # pydantic counts only the valid entries: the inner errors say what is wrong
        base = _join(prefix, _location(error["loc"]))
        if error["type"] == "union_tag_invalid":
            base = _join(base, "type")
        cause = (error.get("ctx") or {}).get("error")
        if isinstance(cause, FieldError):
            for path, message in cause.problems:
                yield TaskProblem(_join(base, path), message)
        else:
            yield TaskProblem(base, _message(error))


def _has_inner_errors(error: ErrorDetails, errors: list[ErrorDetails]) -> bool:
    loc = tuple(error["loc"])
    return any(len(other["loc"]) > len(loc) and tuple(other["loc"][: len(loc)]) == loc for other in errors)


def _location(loc: Sequence[int | str]) -> str:
    path = ""
    for part in loc:
        if part in TARGET_KINDS:
            continue  # the tag pydantic puts after a target: the kind is the target's own 'type'
        path = _join(path, f"[{part}]" if isinstance(part, int) else str(part))
    return path


def _join(prefix: str, path: str) -> str:
    if not prefix:
        return path
    if not path:
        return prefix
    return prefix + (path if path.startswith("[") else f".{path}")


#: Messages for pydantic's error types, formatted with the error's context.
_MESSAGES = {
    "missing": "required",
    "extra_forbidden": "unknown field",
    "greater_than": "must be > {gt}",
    "greater_than_equal": "must be >= {ge}",
    "less_than": "must be < {lt}",
    "less_than_equal": "must be <= {le}",
    "too_short": "must have at least {min_length} entr{plural}",
    "string_too_short": "must not be empty",
    "string_too_long": "must be at most {max_length} characters",
    "enum": "must be one of {expected}",
    "literal_error": "must be one of {expected}",
    "union_tag_invalid": f"must be one of {', '.join(TARGET_KINDS[1:])} (absent: sidereal), got {{tag}}",
    "float_type": "expected a number",
    "int_type": "expected a whole number",
    "bool_type": "expected true or false",
    "string_type": "expected text",
    "dict_type": "expected a mapping",
    "model_type": "expected a mapping",
    "model_attributes_type": "expected a mapping",
    "tuple_type": "expected a list",
    "list_type": "expected a list",
    "datetime_type": "expected a date and time (ISO 8601, e.g. 2026-11-10T18:00:00Z)",
    "datetime_parsing": "expected a date and time (ISO 8601, e.g. 2026-11-10T18:00:00Z)",
    "datetime_from_date_parsing": "expected a date and time (ISO 8601, e.g. 2026-11-10T18:00:00Z)",
}


def _message(error: ErrorDetails) -> str:
    template = _MESSAGES.get(error["type"])
    context: dict[str, Any] = dict(error.get("ctx") or {})
    if template is None:
        return str(error["msg"])
    context["plural"] = "y" if context.get("min_length") == 1 else "ies"
    text = template.format(**{key: _plain(value) for key, value in context.items()})
    if error["type"].endswith(("_type", "_parsing")):
        text += f", got {_describe(error['input'])}"
    return text


def _plain(value: object) -> object:
    # 0.0 reads better as 0 in "must be > 0".
    if isinstance(value, float) and value.is_integer():
        return int(value)
    return value


def _describe(value: object) -> str:
    if isinstance(value, Mapping):
        return "a mapping"
    if isinstance(value, list | tuple):
        return "a list"
    return f"{type(value).__name__} {value!r}" if value is not None else "nothing (null)"
