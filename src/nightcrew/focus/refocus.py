"""When to focus again, pure: the triggers, and the cause that fired first (or none).

A focus found once does not hold all night: the tube's length follows the temperature, a filter of
another thickness moves the focal plane, and a focuser slips. The triggers, each off unless set:

* ``fwhm_rise``: the recent star FWHM is more than this fraction above the FWHM after the last focus
  (0.25: 25 % wider) - whatever the cause, the stars say it;
* ``temperature_change``: the temperature moved by more than this many °C since the last focus;
* ``interval``: this many seconds have passed since the last focus;
* ``filter_change``: the filter is not the one the last focus was found in.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["FocusState", "RefocusTriggers", "refocus_cause"]


@dataclass(frozen=True)
class RefocusTriggers:
    """Which triggers are on (None or False: off); see the module docstring."""

    fwhm_rise: float | None = None
    temperature_change: float | None = None
    interval: float | None = None
    filter_change: bool = False

    def __post_init__(self) -> None:
        for name in ("fwhm_rise", "temperature_change", "interval"):
            value = getattr(self, name)
            if value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
                raise ValueError(f"{name} must be a number >= 0, got {value!r}")
            if value < 0:
                raise ValueError(f"{name} must be >= 0, got {value!r}")
        if not isinstance(self.filter_change, bool):
            raise ValueError(f"filter_change must be true or false, got {self.filter_change!r}")

    @property
    def any(self) -> bool:
        """Whether any trigger is on."""
        return self.filter_change or any(
            value is not None for value in (self.fwhm_rise, self.temperature_change, self.interval)
        )


@dataclass(frozen=True)
class FocusState:
    """What held when the focus was last found (None: not known), and the FWHM of the frames after it."""

    time: float
    temperature: float | None = None
    filter_name: str | None = None
    fwhm: float | None = None


def refocus_cause(
    triggers: RefocusTriggers,
    last: FocusState,
    *,
    time: float,
    temperature: float | None = None,
    filter_name: str | None = None,
    fwhm: float | None = None,
) -> str | None:
    """Why to focus now (the first trigger that fires, as words for the log), or None.

    Args:
        triggers: Which triggers are on.
        last: The state at the last focus.
        time: Clock time now.
        temperature: °C now, None if not known (the temperature trigger then waits).
        filter_name: The filter for the next frame, None if not known.
        fwhm: The recent frames' FWHM, in the unit of ``last.fwhm``; None if not measured.
    """
    rise = triggers.fwhm_rise
    baseline = last.fwhm
    if rise is not None and fwhm is not None and baseline is not None and fwhm > (1.0 + rise) * baseline > 0:
        percent = 100.0 * (fwhm / baseline - 1.0)
        return f"FWHM {fwhm:.2f} is {percent:.0f} % above {baseline:.2f} after the last focus"
    change, before = triggers.temperature_change, last.temperature
    if (
        change is not None
        and temperature is not None
        and before is not None
        and abs(temperature - before) > change
    ):
        return f"temperature {temperature:.1f} °C, {before:.1f} °C at the last focus"
    if triggers.interval is not None and time - last.time > triggers.interval:
        return f"{time - last.time:.0f} s since the last focus"
    if triggers.filter_change and filter_name is not None and filter_name != last.filter_name:
        return f"filter {filter_name}, the last focus was in {last.filter_name}"
    return None
