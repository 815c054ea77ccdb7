"""The server side of the Alpaca wire format: reading requests and shaping replies.

What the ASCOM Alpaca API reference asks of a server, in one place:

* parameters come in the query string (GET) or a form-encoded body (PUT); their names are matched
  without regard to case (``rightascension`` and ``RightAscension`` are the same parameter);
* ``ClientTransactionID`` is echoed back (0 when missing or not an unsigned 32-bit number), and
  every reply carries a ``ServerTransactionID`` that grows with each request;
* a malformed request (missing parameter, a value that is not a number, NaN) is answered with
  HTTP 400 and a plain-text message: :class:`BadRequest`; a well-formed request the device refuses
  gets HTTP 200 with ``ErrorNumber``/``ErrorMessage`` (see :mod:`nightcrew.bridges.alpaca.errors`).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

__all__ = ["AlpacaRequest", "BadRequest", "TransactionCounter", "reply"]

_UINT32_MAX = 2**32 - 1


class BadRequest(Exception):
    """A request the server cannot even read; answered with HTTP 400 and this message."""


class TransactionCounter:
    """Server transaction IDs: 1, 2, 3, ... wrapping within the unsigned 32-bit range."""

    def __init__(self) -> None:
        self._ids = itertools.count(1)

    def next(self) -> int:
        return (next(self._ids) - 1) % _UINT32_MAX + 1


@dataclass(frozen=True)
class AlpacaRequest:
    """One request's parameters (names lower-cased) and the member it is for (for messages)."""

    member: str
    params: Mapping[str, str]

    @classmethod
    def from_params(cls, member: str, *sources: Mapping[str, str]) -> AlpacaRequest:
        """Merge parameter sources (query, then form); names are compared case-insensitively."""
        merged: dict[str, str] = {}
        for source in sources:
            for name, value in source.items():
                merged[name.lower()] = value
        return cls(member, merged)

    @property
    def client_transaction_id(self) -> int:
        return _uint32(self.params.get("clienttransactionid"))

    @property
    def client_id(self) -> int:
        return _uint32(self.params.get("clientid"))

    def string(self, name: str) -> str:
        """The parameter ``name`` as given; BadRequest when it is missing."""
        value = self.params.get(name.lower())
        if value is None:
            raise BadRequest(f"{self.member}: missing parameter {name}")
        return value

    def number(self, name: str) -> float:
        """A finite number; BadRequest for a missing parameter, text, NaN or infinity."""
        text = self.string(name)
        try:
            if not text.isascii():  # Python reads other scripts' digits; Alpaca sends ASCII
                raise ValueError(text)
            value = float(text)
        except ValueError:
            raise BadRequest(f"{self.member}: parameter {name}={text!r} is not a number") from None
        if not math.isfinite(value):
            raise BadRequest(f"{self.member}: parameter {name}={text!r} is not a finite number")
        return value

    def integer(self, name: str) -> int:
        """A whole number; BadRequest for a missing parameter or anything else."""
        text = self.string(name)
        try:
            if not text.isascii():
                raise ValueError(text)
            return int(text.strip())
        except ValueError:
            raise BadRequest(f"{self.member}: parameter {name}={text!r} is not a whole number") from None

    def boolean(self, name: str) -> bool:
        """``true`` or ``false`` (any case); BadRequest for anything else."""
        text = self.string(name)
        lowered = text.strip().lower()
        if lowered not in ("true", "false"):
            raise BadRequest(f"{self.member}: parameter {name}={text!r} is not true or false")
        return lowered == "true"


def _uint32(text: str | None) -> int:
    """``text`` as an unsigned 32-bit number, or 0 when missing or invalid (the spec's rule)."""
    if text is None:
        return 0
    try:
        value = int(text.strip())
    except ValueError:
        return 0
    return value if 0 <= value <= _UINT32_MAX else 0


def reply(
    request: AlpacaRequest,
    server_transaction_id: int,
    value: Any = None,
    *,
    error_number: int = 0,
    error_message: str = "",
) -> dict[str, Any]:
    """The JSON body of an answer; ``Value`` is left out when there is none (a PUT, an error)."""
    body: dict[str, Any] = {}
    if value is not None and error_number == 0:
        body["Value"] = value
    body["ClientTransactionID"] = request.client_transaction_id
    body["ServerTransactionID"] = server_transaction_id
    body["ErrorNumber"] = error_number
    body["ErrorMessage"] = error_message
    return body
