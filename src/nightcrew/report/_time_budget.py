"""Where the good-weather dark time went, and how long each task took to its first science frame.

:func:`time_budget` gives every instant of the good-weather dark time (Sun below ``sun_limit``,
weather not bad) the first label of :data:`BUDGET_LABELS` that applies:

* ``exposing <type>``: a light frame of that IMAGETYP (object, focus, acquisition, skyflat) exposes
  with the roof open (a frame cut short by bad weather: the seconds it exposed);
* ``dark and bias frames``: calibration frames taken in the dark time (the shutter stays closed);
* ``exposing, frame not kept``: the camera exposes (its ExposureStatusChangedEvents) but no frame
  was written: exposures aborted (a camera that cannot stop and keep them, the end of the run),
  frames never written;
* ``readout``: the camera reads out;
* ``slew``: the telescope slews, initialises or parks;
* ``roof opening or closing``: the roof moves although the weather is good;
* ``roof closed``: the rest of the time the roof is not open (e.g. the weather module's wait
  for good weather to last, or the mastermind closing for a gap between tasks);
* ``filter change``: the filter wheel moves;
* ``focus run, between frames``: from the first to the last frame of a focus series;
* ``in a task, camera idle``: a task runs but the camera neither exposes nor reads out (frame
  writing and analysis, acquisition solving, guiding start-up);
* ``no task running``: the roof is open and the mastermind runs nothing (a gap in the schedule,
  waiting for a task's slot, a step of the mastermind's loop).

:func:`acquisitions` measures, per task run, the clock time from its start to the start of its
first science (``object``) frame, and how much of it the telescope slewed and the camera was busy
(acquisition frames are not written, but the camera's status events show them).
Both are pure: the night's records in, clock seconds out.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from nightcrew.report._data import Night, Record, TaskRun, roof_open_intervals, task_runs
from nightcrew.report._metrics import good_dark_intervals, intersect, light_intervals, subtract, total, union

__all__ = ["BUDGET_LABELS", "Acquisition", "acquisitions", "time_budget"]

Interval = tuple[float, float]

#: The labels after the ``exposing <type>`` ones, in the order they are given.
BUDGET_LABELS = (
    "dark and bias frames",
    "exposing, frame not kept",
    "readout",
    "slew",
    "roof opening or closing",
    "roof closed",
    "filter change",
    "focus run, between frames",
    "in a task, camera idle",
    "no task running",
)

#: Telescope states that count as a slew.
_MOVING = frozenset({"slewing", "initializing", "parking"})
#: Roof states in which it moves.
_ROOF_MOVING = frozenset({"moving", "parking", "initializing"})
#: Camera states in which it is busy with a frame.
_CAMERA_BUSY = frozenset({"exposing", "readout"})
#: The event kind of a device's motion state.
_MOTION = "MotionStatusChangedEvent"
#: Focus frames closer than this (clock s) belong to one focus run.
_FOCUS_RUN_GAP_S = 900.0


@dataclass(frozen=True)
class Acquisition:
    """A task run from its start to its first science frame (``first_science`` None: it took none)."""

    task_id: str
    name: str
    start: float
    first_science: float | None
    slewing_s: float
    camera_busy_s: float

    @property
    def seconds(self) -> float | None:
        """Clock seconds from the task's start to its first science exposure."""
        return None if self.first_science is None else self.first_science - self.start


def time_budget(
    night: Night, *, latitude: float, longitude: float, sun_limit: float = -12.0
) -> dict[str, float]:
    """Clock seconds of the good-weather dark time per label (see the module doc); sums to it.

    The ``exposing <type>`` labels come first (sorted by type), then :data:`BUDGET_LABELS`.
    """
    start, end = night.span
    good = good_dark_intervals(night, latitude=latitude, longitude=longitude, sun_limit=sun_limit)
    records = night.records
    roof = roof_open_intervals(records, end)
    layers: list[tuple[str, list[Interval]]] = []
    for kind in sorted({f.image_type for f in night.frames if f.light}):
        frames = [f for f in night.frames if f.image_type == kind]
        layers.append((f"exposing {kind}", light_intervals(frames, roof)))
    layers += [
        ("dark and bias frames", [(f.start, f.end) for f in night.frames if not f.light]),
        ("exposing, frame not kept", _camera(records, frozenset({"exposing"}), end)),
        ("readout", _camera(records, frozenset({"readout"}), end)),
        ("slew", _slews(records, end)),
        ("roof opening or closing", _states(records, "roof", _MOTION, "status", _ROOF_MOVING, end)),
        ("roof closed", subtract([(start, end)], roof)),
        ("filter change", _states(records, "filters", _MOTION, "status", frozenset({"moving"}), end)),
        ("focus run, between frames", _focus_runs(night)),
        ("in a task, camera idle", [(r.start, _end(r, end)) for r in task_runs(records)]),
        ("no task running", [(start, end)]),
    ]
    spent: dict[str, float] = {}
    left = good
    for label, intervals in layers:
        taken = intersect(left, union(intervals))
        spent[label] = total(taken)
        left = subtract(left, taken)
    return spent


def acquisitions(night: Night) -> list[Acquisition]:
    """Every task run that took a science frame, or none but acquisition frames (it failed early).

    Runs that took other frames and no science frame (flats, biases, focus series) are left out.
    """
    end = night.span[1]
    slews = _slews(night.records, end)
    camera = _camera(night.records, _CAMERA_BUSY, end)
    result = []
    for run in task_runs(night.records):
        until = _end(run, end)
        frames = [f for f in night.frames if run.start <= f.start <= until]
        science = [f.start for f in frames if f.image_type == "object"]
        if not science and any(f.image_type != "acquisition" for f in frames):
            continue
        first = min(science) if science else None
        window = [(run.start, first if first is not None else until)]
        result.append(
            Acquisition(
                run.task_id,
                run.name,
                run.start,
                first,
                total(intersect(window, slews)),
                total(intersect(window, camera)),
            )
        )
    return result


def _states(
    records: Sequence[Record], sender: str, kind: str, key: str, states: frozenset[str], end: float
) -> list[Interval]:
    """When ``sender``'s ``kind`` events last said one of ``states`` in their field ``key``."""
    intervals: list[Interval] = []
    since: float | None = None
    for record in records:
        if record.sender != sender or record.kind != kind:
            continue
        inside = str(record.data.get(key, "")) in states
        if inside and since is None:
            since = record.t
        elif not inside and since is not None:
            intervals.append((since, record.t))
            since = None
    if since is not None:
        intervals.append((since, end))
    return intervals


def _slews(records: Sequence[Record], end: float) -> list[Interval]:
    return _states(records, "telescope", _MOTION, "status", _MOVING, end)


def _camera(records: Sequence[Record], states: frozenset[str], end: float) -> list[Interval]:
    return _states(records, "camera", "ExposureStatusChangedEvent", "current", states, end)


def _end(run: TaskRun, night_end: float) -> float:
    return run.end if run.end is not None else night_end


def _focus_runs(night: Night) -> list[Interval]:
    """First to last frame of each focus run (focus frames less than a gap apart)."""
    spans: list[Interval] = []
    for t in sorted(f.start for f in night.frames if f.image_type == "focus"):
        if spans and t - spans[-1][1] < _FOCUS_RUN_GAP_S:
            spans[-1] = (spans[-1][0], t)
        else:
            spans.append((t, t))
    return spans
