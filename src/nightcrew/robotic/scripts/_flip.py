"""The meridian flip between two exposures: when, as a pure function, and how, as steps.

A German-equatorial mount keeps its pier side while it tracks, so a target crossing the meridian
raises the counterweight. Before each exposure the script asks :func:`flip_wait` whether that frame
would end more than ``flip_past_meridian`` degrees past the meridian on the counterweight-up side;
if so it waits until the target is :data:`FLIP_BEYOND_MERIDIAN` past the meridian, stops guiding,
slews to the same target again (the mount ends on the other side), re-centres by the acquisition,
refocuses if asked to (:class:`RefocusAfterFlip`: the optics sag differently on the other side),
restarts guiding and goes on.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from nightcrew.astro.pier import SIDEREAL_RATE, counterweight_up
from nightcrew.config.options import dataclass_from_options
from nightcrew.interfaces import PierSide

__all__ = ["FLIP_BEYOND_MERIDIAN", "RefocusAfterFlip", "flip_wait"]

#: Degrees past the meridian (12 clock seconds) a flip waits for, so that the mount's own choice of
#: side, which turns at the meridian, is not left to rounding.
FLIP_BEYOND_MERIDIAN = 0.05


def flip_wait(ha: float, seconds: float, side: PierSide, past_meridian: float) -> float | None:
    """Clock seconds to wait before a flip, or None when the next exposure needs none.

    Args:
        ha: Hour angle of the target now, degrees.
        seconds: How long the next exposure (with its read-out) takes.
        side: The mount's pier side now (UNKNOWN: never flip).
        past_meridian: Degrees the mount may track past the meridian with its counterweight up
            (below the mount's own limit).
    """
    if side is PierSide.UNKNOWN:
        return None
    if counterweight_up(ha + seconds * SIDEREAL_RATE, side) <= past_meridian:
        return None
    # The other side has its counterweight down only once the target is past the meridian.
    return max(0.0, (FLIP_BEYOND_MERIDIAN - counterweight_up(ha, side)) / SIDEREAL_RATE)


@dataclass(frozen=True)
class RefocusAfterFlip:
    """A focus series after each flip, by the IAutoFocus module ``focus``: ``count`` frames of
    ``exposure_time`` seconds, ``step`` mm apart."""

    focus: str = "focus"
    count: int = 7
    step: float = 0.05
    exposure_time: float = 5.0

    def __post_init__(self) -> None:
        if not (isinstance(self.focus, str) and self.focus):
            raise ValueError(f"focus must name an IAutoFocus module, got {self.focus!r}")
        if not (isinstance(self.count, int) and self.count >= 3):
            raise ValueError(f"count must be an integer >= 3, got {self.count!r}")
        for name in ("step", "exposure_time"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be > 0, got {value!r}")

    @classmethod
    def from_options(cls, options: Mapping[str, Any]) -> RefocusAfterFlip:
        """From the script's ``refocus_after_flip`` mapping; ValueError naming an unknown key."""
        return dataclass_from_options(cls, options)
