"""The server side of the Alpaca wire format: reading requests and shaping replies.

What the ASCOM Alpaca API reference asks of a server, in one place:

* parameters come in the query string (GET) or a form-encoded body (PUT). Query names are matched
  without regard to case (``rightascension`` and ``RightAscension`` are the same parameter), form
  names exactly (a PUT with ``rightascension`` lacks ``RightAscension``: HTTP 400, as ConformU
  checks; a mis-cased ``clienttransactionid`` in a form is ignored and 0 is echoed);
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

import numpy.typing as npt

__all__ = ["AlpacaRequest", "BadRequest", "ImageArray", "TransactionCounter", "reply"]

_UINT32_MAX = 2**32 - 1


class BadRequest(Exception):
    """A request the server cannot even read; answered with HTTP 400 and this message."""


@dataclass(frozen=True)
class ImageArray:
    """A frame's pixels (``[y, x]``, as nightcrew stores them) to be sent as ImageArray."""

    data: npt.NDArray[Any]


class TransactionCounter:
    """Server transaction IDs: 1, 2, 3, ... wrapping within the unsigned 32-bit range."""

    def __init__(self) -> None:
        self._ids = itertools.count(1)

    def next(self) -> int:
        return (next(self._ids) - 1) % _UINT32_MAX + 1


@dataclass(frozen=True)
class AlpacaRequest:
    """One request's parameters and the member it is for (for messages). Names are lower-cased
    unless ``case_sensitive`` (a PUT's form)."""

    member: str
    params: Mapping[str, str]
    case_sensitive: bool = False

    @classmethod
    def from_query(cls, member: str, query: Mapping[str, str]) -> AlpacaRequest:
        """A GET's query parameters; names are compared case-insensitively."""
        return cls(member, {name.lower(): value for name, value in query.items()})

    @classmethod
    def from_form(cls, member: str, form: Mapping[str, str]) -> AlpacaRequest:
        """A PUT's form parameters; names must be spelled as the specification does."""
        return cls(member, dict(form), case_sensitive=True)

    def _get(self, name: str) -> str | None:
        return self.params.get(name if self.case_sensitive else name.lower())

    @property
    def client_transaction_id(self) -> int:
        return _uint32(self._get("ClientTransactionID"))

    @property
    def client_id(self) -> int:
        return _uint32(self._get("ClientID"))

    def string(self, name: str) -> str:
        """The parameter ``name`` as given; BadRequest when it is missing."""
        value = self._get(name)
        if value is None:
            miscased = [given for given in self.params if given.lower() == name.lower()]
            hint = f" (got {miscased[0]}: form parameter names are case sensitive)" if miscased else ""
            raise BadRequest(f"{self.member}: missing parameter {name}{hint}")
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
