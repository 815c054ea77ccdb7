"""Exposure-time functions of the solar altitude, per filter and binning.

A function gives the exposure time in seconds that brings a twilight flat to the target level when
the Sun stands ``h`` degrees high, e.g. ``exp(-0.92*(h + 4.5))``: the twilight sky fades
exponentially with the Sun's depression, so ``ln t`` is linear in ``h`` and ``exp(a*(h + b))`` is
the natural form (``b`` is minus the altitude where one second suffices). Functions are safe
expressions (:mod:`nightcrew.focus.expression`) in the single variable ``h``.

Configuration maps filter name → binning (``"2x2"``) → function::

    functions:
      V: {"1x1": "exp(-0.92*(h + 4.5))", "2x2": "exp(-0.92*(h + 6.0))"}
      none: {"1x1": "exp(-0.92*(h + 6.5))"}     # a camera without a filter wheel
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.focus.expression import Expression, ExpressionError

__all__ = ["NO_FILTER", "ExposureTimeFunctions", "binning_key", "parse_binning"]

#: Filter key of a camera without a filter wheel.
NO_FILTER = "none"
#: The variable of every function: solar altitude in degrees.
SUN_ALTITUDE = "h"

_BINNING = re.compile(r"^\s*(\d+)\s*x\s*(\d+)\s*$")


def parse_binning(text: str) -> tuple[int, int]:
    """``"2x2"`` → (2, 2); ValueError for anything else."""
    match = _BINNING.match(str(text))
    if not match or int(match.group(1)) < 1 or int(match.group(2)) < 1:
        raise ValueError(f"expected a binning like '2x2', got {text!r}")
    return int(match.group(1)), int(match.group(2))


def binning_key(x: int, y: int) -> str:
    return f"{x}x{y}"


class ExposureTimeFunctions:
    """Exposure time (s) for a filter and binning as a function of the solar altitude (deg).

    Args:
        functions: Filter → binning → function text (see module docstring).
        key: Configuration key for error messages.

    Raises:
        ConfigError: naming ``key.<filter>.<binning>`` for the first bad entry.
    """

    def __init__(self, functions: Mapping[str, Mapping[str, str]], key: str = "functions") -> None:
        self._functions: dict[tuple[str, str], Expression] = {}
        if not isinstance(functions, Mapping) or not functions:
            raise ConfigError("needs at least one filter with a function per binning", key=key)
        for filter_name, per_binning in functions.items():
            if not isinstance(per_binning, Mapping) or not per_binning:
                raise ConfigError(
                    "expected a mapping of binning ('2x2') to function", key=f"{key}.{filter_name}"
                )
            for binning, text in per_binning.items():
                where = f"{key}.{filter_name}.{binning}"
                try:
                    x, y = parse_binning(str(binning))
                    expression = Expression(str(text))
                except (ValueError, ExpressionError) as exc:
                    raise ConfigError(str(exc), key=where) from None
                extra = sorted(expression.names - {SUN_ALTITUDE})
                if extra:
                    raise ConfigError(
                        f"a function may only use '{SUN_ALTITUDE}' (solar altitude), not {', '.join(extra)}",
                        key=where,
                    )
                self._functions[(str(filter_name), binning_key(x, y))] = expression

    def combinations(self) -> list[tuple[str, str]]:
        """(filter, binning key) pairs that have a function, in configuration order."""
        return list(self._functions)

    def function(self, filter_name: str | None, binning: tuple[int, int]) -> Expression:
        """The function for this filter (None: no filter wheel) and binning; ValueError if none."""
        key = (filter_name or NO_FILTER, binning_key(*binning))
        if key not in self._functions:
            known = ", ".join(f"{f}/{b}" for f, b in self._functions)
            raise ValueError(f"no exposure-time function for filter {key[0]}, binning {key[1]}; have {known}")
        return self._functions[key]

    @staticmethod
    def evaluate(function: Expression, sun_altitude: float) -> float:
        """Seconds for ``sun_altitude``; ValueError if the function gives no positive time there."""
        seconds = function.evaluate({SUN_ALTITUDE: sun_altitude})
        if not seconds > 0:
            raise ValueError(f"{function.text} gives {seconds} s at h={sun_altitude:.2f}°, expected > 0")
        return seconds

    def to_plain(self) -> dict[str, dict[str, Any]]:
        plain: dict[str, dict[str, Any]] = {}
        for (filter_name, binning), expression in self._functions.items():
            plain.setdefault(filter_name, {})[binning] = expression.text
        return plain
