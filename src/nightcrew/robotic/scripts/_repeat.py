"""Pure timing of REPEAT_EXPOSE: which exposures still fit before the repeat duration ends."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["RepeatTiming"]


@dataclass
class RepeatTiming:
    """Keeps a REPEAT_EXPOSE within its duration (clock seconds throughout).

    The first cycle through the instrument configs is always completed (a REPEAT_EXPOSE counts as
    done after one cycle); after it, an exposure starts only if it is expected to end, read-out
    included, before ``start + duration``. The read-out (overhead) is learnt from the frames taken.

    Args:
        start: When the repetitions began.
        duration: The configuration's ``repeat_duration``.
    """

    start: float
    duration: float
    overhead: float = 0.0

    @property
    def deadline(self) -> float:
        return self.start + self.duration

    def fits(self, now: float, exposure_time: float) -> bool:
        """Whether an exposure of ``exposure_time`` started at ``now`` ends by the deadline."""
        return now + exposure_time + self.overhead <= self.deadline

    def record(self, started: float, ended: float, exposure_time: float) -> None:
        """A frame of ``exposure_time`` took from ``started`` to ``ended``: learn the overhead."""
        self.overhead = max(self.overhead, ended - started - exposure_time)
