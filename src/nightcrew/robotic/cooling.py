"""When and how fast a camera cools: the decisions of the cooling schedule, pure.

The night of a cooled camera: it cools down at dusk, ramping its set point by at most
``ramp_rate`` °C per minute from the chip's temperature, starting early enough to reach the set
point ``lead_time`` seconds before the Sun sinks below ``ready_sun_altitude`` (the first frames
that need the cold chip: the dusk flats); it holds the set point through the night; once the Sun
rises above ``warm_sun_altitude`` it ramps the set point up to the temperature the chip had before
cooling and switches the cooler off - when there, or after ``warm_up_time_limit`` seconds at the
latest (a warm-up that never ends keeps the cooler on all day).

:func:`cooling_command` takes the moment, the chip and what was commanded last and returns what to
command now; :class:`~nightcrew.modules.camera.cooling.CoolingSchedule` feeds it from the camera
and the Sun.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

from nightcrew.interfaces import CoolingStatus

__all__ = [
    "CoolerCommand",
    "CoolingPhase",
    "CoolingPlan",
    "cooler_settled",
    "cooling_command",
    "ramp_duration",
    "ramp_step",
]


class CoolingPhase(StrEnum):
    """Where in its night the cooler is."""

    OFF = "off"  # day: cooler off
    COOLING = "cooling"  # ramping down to the set point
    HOLDING = "holding"  # at the set point
    WARMING = "warming"  # ramping up at dawn


@dataclass(frozen=True)
class CoolingPlan:
    """A camera's cooling night (see the module docstring).

    Raises:
        ValueError: a value out of range, naming it.
    """

    setpoint: float  # °C
    ramp_rate: float = 3.0  # °C per minute, both ways
    ready_sun_altitude: float = -3.0  # degrees; at the set point before the Sun sets below this
    warm_sun_altitude: float = -3.0  # degrees; warm up when the Sun rises above this
    lead_time: float = 600.0  # seconds at the set point before the first frame that needs it
    warm_up_time_limit: float = 1800.0  # seconds; the cooler is off this long after warm-up began

    def __post_init__(self) -> None:
        if not (math.isfinite(self.setpoint) and -100.0 <= self.setpoint <= 50.0):
            raise ValueError(f"setpoint must be within -100..50 °C, got {self.setpoint}")
        if not (math.isfinite(self.ramp_rate) and self.ramp_rate > 0):
            raise ValueError(f"ramp_rate must be > 0 °C per minute, got {self.ramp_rate}")
        for name in ("ready_sun_altitude", "warm_sun_altitude"):
            if not -90.0 <= getattr(self, name) <= 90.0:
                raise ValueError(f"{name} must be within -90..90 degrees, got {getattr(self, name)}")
        if not self.lead_time >= 0:
            raise ValueError(f"lead_time must be >= 0 seconds, got {self.lead_time}")
        if not self.warm_up_time_limit > 0:
            raise ValueError(f"warm_up_time_limit must be > 0 seconds, got {self.warm_up_time_limit}")


@dataclass(frozen=True)
class CoolerCommand:
    """What to tell the camera: cooler on or off, the set point, and why."""

    phase: CoolingPhase
    enabled: bool
    setpoint: float


def ramp_duration(start: float, target: float, ramp_rate: float) -> float:
    """Seconds a ramp from ``start`` to ``target`` °C takes at ``ramp_rate`` °C per minute."""
    return abs(target - start) / ramp_rate * 60.0


def ramp_step(commanded: float, target: float, ramp_rate: float, seconds: float) -> float:
    """The set point ``seconds`` after ``commanded``, moving towards ``target`` at ``ramp_rate``."""
    step = ramp_rate * max(0.0, seconds) / 60.0
    return max(target, commanded - step) if target < commanded else min(target, commanded + step)


def cooling_command(
    plan: CoolingPlan,
    *,
    now: float,
    ready_at: float,
    warm_at: float,
    temperature: float,
    warm_temperature: float,
    last: CoolerCommand | None,
    last_time: float,
    warming_since: float | None,
) -> CoolerCommand:
    """What to command at ``now`` (Unix seconds).

    Args:
        plan: The cooling night.
        ready_at: Next time the Sun sets below ``plan.ready_sun_altitude``.
        warm_at: Next time the Sun rises above ``plan.warm_sun_altitude``.
        temperature: The chip's temperature now, °C.
        warm_temperature: Where a warm-up ends: the chip's temperature before it was cooled.
        last: The command of ``last_time``; None at the start.
        warming_since: When the current warm-up began (None: not warming).
    """
    night = warm_at < ready_at  # the Sun rises above the warm limit before it sets again
    cool_from = ready_at - plan.lead_time - ramp_duration(warm_temperature, plan.setpoint, plan.ramp_rate)
    elapsed = now - last_time
    if night or now >= cool_from:
        # A ramp starts from the chip when the cooler is switched on, else from the last set point.
        if last is not None and last.enabled:
            setpoint = ramp_step(last.setpoint, plan.setpoint, plan.ramp_rate, elapsed)
        else:
            setpoint = max(plan.setpoint, temperature)
        phase = CoolingPhase.HOLDING if setpoint == plan.setpoint else CoolingPhase.COOLING
        return CoolerCommand(phase, True, setpoint)
    if last is None or not last.enabled:
        return CoolerCommand(CoolingPhase.OFF, False, plan.setpoint)
    # Day with the cooler on: warm up, then off once warm or out of time.
    timed_out = warming_since is not None and now - warming_since >= plan.warm_up_time_limit
    setpoint = ramp_step(last.setpoint, warm_temperature, plan.ramp_rate, elapsed)
    if timed_out or (setpoint >= warm_temperature and temperature >= warm_temperature - 1.0):
        return CoolerCommand(CoolingPhase.OFF, False, plan.setpoint)
    return CoolerCommand(CoolingPhase.WARMING, True, setpoint)


def cooler_settled(status: CoolingStatus, margin: float) -> bool:
    """Whether a frame taken now would be at the set point (within ``margin`` °C); a camera that
    does not cool, or does not tell its temperature, is as settled as it gets."""
    if not status.enabled or status.temperature is None:
        return True
    return abs(status.temperature - status.setpoint) <= margin
