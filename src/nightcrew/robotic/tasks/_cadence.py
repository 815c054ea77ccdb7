"""Cadence requests (as in the LCO portal): one request repeated every ``period`` hours.

A request with a ``cadence`` instead of ``windows`` is expanded when its group is built: one
request per visit, each with one window ``jitter`` hours wide centred on ``start + k * period``
(k = 0, 1, ...; the last window ends by ``end``), each observed once. The visits keep the cadence,
so their progress can be told (:func:`cadence_visit`).
"""

from __future__ import annotations

from datetime import datetime, timedelta
from typing import Self

from pydantic import Field, model_validator

from nightcrew.robotic.tasks._base import Number, TaskModel, UtcDatetime, raise_problems

__all__ = ["MAX_CADENCE_VISITS", "Cadence", "cadence_visit"]

#: Most visits one cadence may expand to (a typo in ``period`` should not make 10,000 tasks).
MAX_CADENCE_VISITS = 1000


class Cadence(TaskModel):
    """Visits every ``period`` hours from ``start`` to ``end``, each within ``jitter`` hours.

    Args:
        start: Centre of the first visit's window.
        end: No visit's window ends after this.
        period: Hours between the centres of two visits' windows, > 0.
        jitter: Width of each visit's window in hours, > 0 and at most ``period`` (windows do not
            overlap, so each visit is its own).
    """

    start: UtcDatetime
    end: UtcDatetime
    period: Number = Field(gt=0.0)
    jitter: Number = Field(gt=0.0)

    @model_validator(mode="after")
    def _check(self) -> Self:
        problems = []
        if self.end <= self.start:
            problems.append(("end", f"must be after start ({self.start.isoformat()})"))
        elif self.jitter > self.period:
            problems.append(("jitter", f"must be at most the period ({self.period:g} h)"))
        elif not self.windows():
            problems.append(("end", f"leaves no room for a window of {self.jitter:g} h after start"))
        elif len(self.windows()) > MAX_CADENCE_VISITS:
            problems.append(("period", f"gives more than {MAX_CADENCE_VISITS} visits"))
        raise_problems(problems)
        return self

    def windows(self) -> list[tuple[datetime, datetime]]:
        """The visits' windows, in order (bounded: stops at ``MAX_CADENCE_VISITS`` + 1)."""
        half, step = timedelta(hours=self.jitter / 2), timedelta(hours=self.period)
        found: list[tuple[datetime, datetime]] = []
        centre = self.start
        while centre + half <= self.end and len(found) <= MAX_CADENCE_VISITS:
            found.append((centre - half, centre + half))
            centre += step
        return found


def cadence_visit(cadence: Cadence, window_start: datetime) -> tuple[int, int]:
    """(visit number from 1, number of visits) of the visit whose window starts at ``window_start``."""
    starts = [start for start, _ in cadence.windows()]
    nearest = min(range(len(starts)), key=lambda k: abs((starts[k] - window_start).total_seconds()))
    return nearest + 1, len(starts)
