"""Getting sensor values out of what remote stations send: JSON documents and CSV logs."""

from __future__ import annotations

import csv
import io
from collections.abc import Mapping
from datetime import UTC, datetime
from typing import Any

from nightcrew.errors import InvalidArgumentError

__all__ = ["json_pointer", "last_csv_row", "parse_number", "parse_time"]


def json_pointer(document: Any, pointer: str) -> Any:
    """The value at ``pointer`` (RFC 6901: ``/current/temp``, ``/sensors/0/value``) in ``document``.

    Raises:
        InvalidArgumentError: The pointer is malformed or leads nowhere.
    """
    if pointer == "":
        return document
    if not pointer.startswith("/"):
        raise InvalidArgumentError(f"JSON pointer {pointer!r} must start with '/'")
    value = document
    for raw in pointer[1:].split("/"):
        token = raw.replace("~1", "/").replace("~0", "~")
        if isinstance(value, Mapping) and token in value:
            value = value[token]
        elif isinstance(value, list) and token.isdigit() and int(token) < len(value):
            value = value[int(token)]
        else:
            raise InvalidArgumentError(f"JSON pointer {pointer!r}: nothing at {token!r}")
    return value


def parse_number(value: Any) -> float | None:
    """A sensor value as float: numbers, numeric strings and booleans; None for null or empty."""
    if value is None or value == "":
        return None
    if isinstance(value, bool):
        return 1.0 if value else 0.0
    if isinstance(value, int | float):
        return float(value)
    if isinstance(value, str):
        text = value.strip().lower()
        if text in ("true", "yes"):
            return 1.0
        if text in ("false", "no"):
            return 0.0
        try:
            return float(text)
        except ValueError:
            pass
    raise InvalidArgumentError(f"not a number: {value!r}")


def parse_time(value: Any) -> float:
    """A time as Unix seconds: a number of seconds or an ISO 8601 string (naive means UTC)."""
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            pass
        try:
            parsed = datetime.fromisoformat(value.strip())
        except ValueError as exc:
            raise InvalidArgumentError(f"not a time: {value!r}") from exc
        if parsed.tzinfo is None:
            parsed = parsed.replace(tzinfo=UTC)
        return parsed.timestamp()
    raise InvalidArgumentError(f"not a time: {value!r}")


def last_csv_row(data: bytes, encoding: str = "utf-8") -> dict[str, str]:
    """The last data row of a CSV log with a header line, as column → text.

    Only the header and the last non-empty line are parsed, so a log growing all night stays cheap.

    Raises:
        InvalidArgumentError: No header or no data row.
    """
    lines = [line for line in data.decode(encoding, errors="replace").splitlines() if line.strip()]
    if len(lines) < 2:
        raise InvalidArgumentError("CSV file has no data row below its header")
    header, last = next(csv.reader(io.StringIO(lines[0]))), next(csv.reader(io.StringIO(lines[-1])))
    return {name.strip(): (last[i].strip() if i < len(last) else "") for i, name in enumerate(header)}
