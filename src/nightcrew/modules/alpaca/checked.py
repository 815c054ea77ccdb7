"""Checked values for Alpaca device modules: typed reads of members and checked wait options.

A device that answers ``"abc"`` where the API promises a number would otherwise surface later as a
TypeError far from its cause; :class:`CheckedGets` turns it into an
:class:`~nightcrew.bridges.alpaca.errors.AlpacaReplyError` naming the device, the call and the
value, which a device module reports like any other device error.

A module's own waits (``shutter_timeout``, ``move_timeout`` ...) must end before the timeout the
interface announces to callers, or a caller gives up while the device still moves. Each module lists
them in :attr:`CheckedGets.wait_limits`; the constructor and ``nightcrew check`` (through
``config_value_problems``) check them with the same function.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from typing import Any, ClassVar

from nightcrew.bridges.alpaca.errors import AlpacaReplyError
from nightcrew.errors import ConfigError
from nightcrew.modules.alpaca.device import AlpacaModule

__all__ = ["CheckedGets", "wait_problem"]


def wait_problem(value: object, limit: float) -> str | None:
    """What is wrong with ``value`` as a wait that must end within ``limit`` seconds, or None."""
    if isinstance(value, bool) or not isinstance(value, int | float) or not 0 < value < limit:
        return f"must be within 0..{limit:g} seconds (the announced timeout), got {value!r}"
    return None


class CheckedGets(AlpacaModule):
    """:class:`AlpacaModule` with ``GET``s that check the kind of the value they return, and
    checked wait options."""

    #: Option → the announced timeout (seconds) the module's wait must stay below.
    wait_limits: ClassVar[dict[str, float]] = {}

    @classmethod
    def config_value_problems(cls, values: Mapping[str, Any]) -> Iterator[tuple[str, str]]:
        yield from AlpacaModule.config_value_problems(values)
        for key, limit in cls.wait_limits.items():
            problem = wait_problem(values[key], limit) if key in values else None
            if problem is not None:
                yield key, problem

    def _checked_wait(self, key: str, value: float) -> float:
        """``value`` of the wait option ``key`` (listed in :attr:`wait_limits`); ConfigError if wrong."""
        problem = wait_problem(value, self.wait_limits[key])
        if problem is not None:
            raise ConfigError(problem, key=key)
        return float(value)

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
