"""When to take twilight flats and for how long: the T_min/T_max logic with a measured sky.

The exposure-time function ``f(h)`` says how long a flat at solar altitude ``h`` must be exposed to
reach the target level. The real sky differs from it by a factor (clouds, aerosols, an old
function): :class:`FlatExposureControl` learns that factor from every frame it is shown, so each
next exposure is ``f(h_next) / sky_factor`` — the previous exposure scaled by target/measured level
and by how much the function says the sky changed meanwhile. The first frame of a run is the test
exposure that calibrates the factor; it counts as a flat only if it lands within the tolerance.

Exposure times must stay within [T_min, T_max] (shorter ones suffer from the shutter, longer ones
collect stars and dark current):

=========  =====================  =====================  =====================
twilight   t < T_min              T_min <= t <= T_max    t > T_max
=========  =====================  =====================  =====================
dusk       wait (sky darkens)     expose                 stop (only darker)
dawn       stop (only brighter)   expose                 wait (sky brightens)
=========  =====================  =====================  =====================
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

__all__ = ["Decision", "FlatExposureControl", "FlatLimits", "Twilight", "twilight_from_altitudes"]


class Twilight(StrEnum):
    DUSK = "dusk"
    DAWN = "dawn"


class Decision(StrEnum):
    WAIT = "wait"
    EXPOSE = "expose"
    STOP = "stop"


def twilight_from_altitudes(now: float, later: float) -> Twilight:
    """Dusk when the Sun is sinking (``later`` below ``now``), else dawn."""
    return Twilight.DUSK if later < now else Twilight.DAWN


@dataclass(frozen=True)
class FlatLimits:
    """Levels in ADU and exposure limits in seconds.

    Attributes:
        target: Mean level a flat should reach (e.g. 30000).
        bias: Level of a zero-second frame, subtracted before comparing levels (e.g. 1000).
        tolerance: A frame within ±tolerance * (target - bias) of the target counts as a flat.
        saturation: Mean level above which a frame is taken as saturated (its level is a bound only).
        min_exposure: T_min.
        max_exposure: T_max.
    """

    target: float = 30000.0
    bias: float = 0.0
    tolerance: float = 0.2
    saturation: float = 60000.0
    min_exposure: float = 1.0
    max_exposure: float = 30.0

    def __post_init__(self) -> None:
        if not 0 <= self.bias < self.target < self.saturation:
            raise ValueError(
                f"need 0 <= bias < target < saturation, got {self.bias}, {self.target}, {self.saturation}"
            )
        if not 0 < self.tolerance < 1:
            raise ValueError(f"tolerance must be within 0..1, got {self.tolerance}")
        if not 0 < self.min_exposure < self.max_exposure:
            raise ValueError(
                f"need 0 < min_exposure < max_exposure, got {self.min_exposure}, {self.max_exposure}"
            )


#: A saturated frame only says the sky is at least this much brighter than its level suggests.
_SATURATED_FACTOR = 3.0


class FlatExposureControl:
    """Decides and scales the exposures of one run of flats in one filter and binning.

    Args:
        limits: Target level, bias, tolerance and T_min/T_max.
        twilight: Dusk or dawn (see the table in the module docstring).
    """

    def __init__(self, limits: FlatLimits, twilight: Twilight) -> None:
        self.limits = limits
        self.twilight = twilight
        #: Measured sky brightness / brightness the function assumes; 1 until a frame was seen.
        self.sky_factor = 1.0
        self.calibrated = False

    def exposure_time(self, modelled: float) -> float:
        """The exposure time for now, from the function's time ``modelled`` at the current altitude."""
        return modelled / self.sky_factor

    def decide(self, exposure_time: float) -> Decision:
        low, high = self.limits.min_exposure, self.limits.max_exposure
        if low <= exposure_time <= high:
            return Decision.EXPOSE
        too_bright = exposure_time < low
        if self.twilight is Twilight.DUSK:
            return Decision.WAIT if too_bright else Decision.STOP
        return Decision.STOP if too_bright else Decision.WAIT

    def clip(self, exposure_time: float) -> float:
        return min(self.limits.max_exposure, max(self.limits.min_exposure, exposure_time))

    def learn(self, exposure_time: float, modelled: float, level: float) -> bool:
        """Update the sky factor from a frame; True if the frame is a good flat.

        Args:
            exposure_time: Seconds the frame was exposed.
            modelled: The function's time at the altitude of that exposure.
            level: The frame's mean (or median) level in ADU.
        """
        limits = self.limits
        signal = level - limits.bias
        wanted = limits.target - limits.bias
        if not math.isfinite(signal) or signal <= 0:
            # No light at all (roof closed?): the sky is far darker than thought.
            self.sky_factor *= 0.1
            self.calibrated = True
            return False
        saturated = level >= limits.saturation
        # The sky gave signal/exposure_time per second where the function expected wanted/modelled.
        factor = (signal / exposure_time) / (wanted / modelled)
        self.sky_factor = factor * (_SATURATED_FACTOR if saturated else 1.0)
        self.calibrated = True
        return not saturated and abs(signal - wanted) <= limits.tolerance * wanted
