"""A cooled chip's temperature: a thermo-electric cooler against the ambient air, pure.

The cooler holds at most ``max_delta`` °C below ``ambient``; the chip follows the temperature the
cooler aims at (the set point, or the coldest it can reach) as a first-order lag of
``time_constant`` seconds, and warms back to ambient the same way when switched off. The state is
advanced by the exact solution, so a step of an hour equals sixty steps of a minute. The power is
what holding the aim takes: ``(ambient - aim) / max_delta`` - 100 % for a set point out of reach,
which is how an unreachable set point shows on a real camera too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["ChipTemperature", "CoolerModel", "advance_chip"]


@dataclass(frozen=True)
class CoolerModel:
    """The physics of one camera's cooler.

    Raises:
        ValueError: a value out of range, naming it.
    """

    ambient: float = 10.0  # °C around the camera
    max_delta: float = 40.0  # °C below ambient at full power
    time_constant: float = 90.0  # seconds for the chip to close 63 % of a gap

    def __post_init__(self) -> None:
        if not math.isfinite(self.ambient) or not -60.0 <= self.ambient <= 60.0:
            raise ValueError(f"ambient must be within -60..60 °C, got {self.ambient}")
        if not (math.isfinite(self.max_delta) and self.max_delta > 0):
            raise ValueError(f"max_delta must be > 0 °C, got {self.max_delta}")
        if not (math.isfinite(self.time_constant) and self.time_constant > 0):
            raise ValueError(f"time_constant must be > 0 seconds, got {self.time_constant}")

    @property
    def coldest(self) -> float:
        """The lowest temperature the cooler can hold, °C."""
        return self.ambient - self.max_delta

    def aim(self, enabled: bool, setpoint: float) -> float:
        """The temperature the chip tends to: the set point within reach, else ambient or coldest."""
        return min(self.ambient, max(setpoint, self.coldest)) if enabled else self.ambient

    def power(self, enabled: bool, setpoint: float) -> float:
        """Cooler power in percent while aiming at ``setpoint``."""
        if not enabled:
            return 0.0
        if setpoint < self.coldest:
            return 100.0
        return 100.0 * max(0.0, self.ambient - self.aim(enabled, setpoint)) / self.max_delta


@dataclass(frozen=True)
class ChipTemperature:
    """The chip at one moment: its temperature (°C) and the time (Unix seconds)."""

    time: float
    temperature: float


def advance_chip(
    model: CoolerModel, state: ChipTemperature, now: float, *, enabled: bool, setpoint: float
) -> ChipTemperature:
    """The chip at ``now``, with the cooler as it was since ``state.time``."""
    seconds = max(0.0, now - state.time)
    aim = model.aim(enabled, setpoint)
    temperature = aim + (state.temperature - aim) * math.exp(-seconds / model.time_constant)
    return ChipTemperature(max(now, state.time), temperature)
