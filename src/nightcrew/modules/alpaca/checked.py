"""Typed reads of Alpaca members: a reply holding the wrong kind of value is one clear error.

A device that answers ``"abc"`` where the API promises a number would otherwise surface later as a
TypeError far from its cause; :class:`CheckedGets` turns it into an
:class:`~nightcrew.bridges.alpaca.errors.AlpacaReplyError` naming the device, the call and the
value, which a device module reports like any other device error.
"""

from __future__ import annotations

import math
from typing import Any

from nightcrew.bridges.alpaca.errors import AlpacaReplyError
from nightcrew.modules.alpaca.device import AlpacaModule

__all__ = ["CheckedGets"]


class CheckedGets(AlpacaModule):
    """:class:`AlpacaModule` with ``GET``s that check the kind of the value they return."""

    def _bad_value(self, member: str, value: Any, wanted: str) -> AlpacaReplyError:
        return AlpacaReplyError(f"{self.device.name}: GET {member}: {value!r} is not {wanted}")

    async def _get_number(self, member: str, **params: Any) -> float:
        """A finite number (Alpaca Double or Int)."""
        value = await self._get(member, **params)
        if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
            raise self._bad_value(member, value, "a finite number")
        return float(value)

    async def _get_integer(self, member: str, **params: Any) -> int:
        """An integer (Alpaca Int)."""
        value = await self._get(member, **params)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self._bad_value(member, value, "an integer")
        return value

    async def _get_flag(self, member: str, **params: Any) -> bool:
        """True or false (Alpaca Boolean)."""
        value = await self._get(member, **params)
        if not isinstance(value, bool):
            raise self._bad_value(member, value, "true or false")
        return value

    async def _get_text(self, member: str, **params: Any) -> str:
        """A string (Alpaca String)."""
        value = await self._get(member, **params)
        if not isinstance(value, str):
            raise self._bad_value(member, value, "a string")
        return value
