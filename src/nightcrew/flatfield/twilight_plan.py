"""In which order to take several flat-field combinations so that as many as possible fit the twilight.

Each combination (filter, binning) can only be flatted while its exposure time ``f(h)`` lies
within [T_min, T_max]; that *opening* moves with the filter's throughput. At dusk the sky fades,
so a combination needing long exposures closes first; at dawn it brightens, so one needing short
exposures closes first. :func:`plan_twilight` therefore:

1. finds every combination's opening (from ``now`` on, to ``step`` seconds, with the modelled
   sky) and how long its ``count`` flats take there (exposures plus ``overhead`` each);
2. admits combinations by falling priority, each only if all admitted ones still finish inside
   their openings when run by earliest closing (the order that fits most, for a given set);
3. returns the admitted ones in that order, then the others (no opening, or no room), which may
   still be tried if the sky turns out brighter than modelled.

Pure: the Sun's altitude comes in as a function of Unix time.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

from nightcrew.errors import ConfigError
from nightcrew.flatfield.control import FlatLimits
from nightcrew.flatfield.exptime import ExposureTimeFunctions
from nightcrew.flatfield.schedule import FlatTask

__all__ = ["PlannedFlats", "TwilightPlanner", "plan_twilight"]

#: The Sun's altitude in degrees at a Unix time.
SunAltitude = Callable[[float], float]


@dataclass(frozen=True)
class PlannedFlats:
    """One combination in the plan.

    Attributes:
        task: The combination and its count.
        opens, closes: Unix times between which its exposure times are within limits (None: never
            within the horizon).
        start, end: When the plan expects it to start and end (None: not admitted).
    """

    task: FlatTask
    opens: float | None
    closes: float | None
    start: float | None
    end: float | None = None

    @property
    def fits(self) -> bool:
        return self.start is not None


def plan_twilight(
    tasks: Sequence[FlatTask],
    functions: ExposureTimeFunctions,
    limits: FlatLimits,
    sun: SunAltitude,
    now: float,
    *,
    overhead: float = 10.0,
    horizon: float = 7200.0,
    step: float = 30.0,
) -> list[PlannedFlats]:
    """The combinations in the order to take them (``tasks`` is by falling priority; see module doc).

    Args:
        tasks: The combinations, highest priority first.
        functions: Exposure time per filter and binning as a function of the Sun's altitude.
        limits: T_min and T_max.
        sun: The Sun's altitude at a Unix time.
        now: Unix time the flats can start.
        overhead: Seconds per flat besides the exposure (read-out, pointing).
        horizon: Seconds ahead to look for openings.
        step: Resolution in seconds.

    Raises:
        ValueError: A combination has no exposure-time function.
    """
    times = [now + step * i for i in range(int(horizon / step) + 1)]
    altitudes = [sun(t) for t in times]
    seconds = {task.key: _modelled(functions, task, altitudes) for task in tasks}
    openings = {task.key: _opening(times, seconds[task.key], limits) for task in tasks}

    def duration(task: FlatTask, start: float) -> float:
        """Seconds ``task.count`` flats take from ``start`` (exposure times follow the Sun)."""
        t, series = start, seconds[task.key]
        for _ in range(task.count):
            index = min(len(times) - 1, max(0, round((t - now) / step)))
            t += min(limits.max_exposure, max(limits.min_exposure, series[index])) + overhead
        return t - start

    def schedule(chosen: list[FlatTask]) -> dict[str, tuple[float, float]] | None:
        """(start, end) when run by earliest closing; None if one does not end in its opening."""
        spans: dict[str, tuple[float, float]] = {}
        t = now
        for task in sorted(chosen, key=lambda c: _closes(openings[c.key])):
            opens, closes = openings[task.key] or (0.0, 0.0)
            start = max(t, opens)
            t = start + duration(task, start)
            spans[task.key] = (start, t)
            if t > closes + step:  # the resolution of the openings
                return None
        return spans

    admitted: list[FlatTask] = []
    for task in tasks:
        if openings[task.key] is not None and schedule([*admitted, task]) is not None:
            admitted.append(task)
    spans = schedule(admitted) or {}
    planned = sorted(admitted, key=lambda t: spans[t.key])
    rest = [task for task in tasks if task not in admitted]
    result: list[PlannedFlats] = []
    for task in [*planned, *rest]:
        opening = openings[task.key]
        opens, closes = opening if opening is not None else (None, None)
        start, end = spans.get(task.key, (None, None))
        result.append(PlannedFlats(task, opens, closes, start, end))
    return result


class TwilightPlanner:
    """:func:`plan_twilight` with its configuration checked once (modules and scripts build one).

    Args:
        functions: Filter -> binning -> exposure-time function (as for the FlatField module).
        min_exposure, max_exposure: T_min and T_max in seconds (as the FlatField module's).
        overhead: Seconds per flat besides the exposure.

    Raises:
        ConfigError: naming the bad key.
    """

    def __init__(
        self,
        functions: Mapping[str, Mapping[str, str]],
        *,
        min_exposure: float = 1.0,
        max_exposure: float = 30.0,
        overhead: float = 10.0,
    ) -> None:
        self.functions = ExposureTimeFunctions(functions, "functions")
        try:
            self.limits = FlatLimits(min_exposure=min_exposure, max_exposure=max_exposure)
        except ValueError as exc:
            raise ConfigError(str(exc), key="min_exposure") from None
        if not overhead >= 0:
            raise ConfigError(f"must be >= 0 s, got {overhead}", key="overhead")
        self.overhead = float(overhead)

    def plan(self, tasks: Sequence[FlatTask], sun: SunAltitude, now: float) -> list[PlannedFlats]:
        """``tasks`` (by falling priority) in the order to take them from ``now``."""
        return plan_twilight(tasks, self.functions, self.limits, sun, now, overhead=self.overhead)


def _modelled(functions: ExposureTimeFunctions, task: FlatTask, altitudes: list[float]) -> list[float]:
    function = functions.function(task.filter_name, task.binning)
    return [functions.evaluate(function, h) for h in altitudes]


def _opening(times: list[float], seconds: list[float], limits: FlatLimits) -> tuple[float, float] | None:
    """The first stretch of ``times`` with exposure times within limits."""
    inside = [limits.min_exposure <= s <= limits.max_exposure for s in seconds]
    if True not in inside:
        return None
    first = inside.index(True)
    last = first
    while last + 1 < len(inside) and inside[last + 1]:
        last += 1
    return times[first], times[last]


def _closes(opening: tuple[float, float] | None) -> float:
    return opening[1] if opening is not None else float("inf")
