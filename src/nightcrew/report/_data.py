"""What a night was, read from its records: the recorder's JSON lines and the frames' FITS headers.

:func:`read_night` is the only function here that touches files; everything else takes the parsed
records and returns plain values (intervals in Unix seconds), so the numbers the report shows and
the tests assert come from the same pure code.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

__all__ = [
    "FRAME_KINDS",
    "Frame",
    "Night",
    "Record",
    "TaskRun",
    "bad_weather_intervals",
    "describe_frames",
    "frame_of_header",
    "parse_time",
    "read_night",
    "roof_open_intervals",
    "task_runs",
]

Interval = tuple[float, float]


@dataclass(frozen=True)
class Record:
    """One line of the recorder: clock time (Unix s), kind (event name), sender, fields."""

    t: float
    kind: str
    sender: str
    data: dict[str, Any]


@dataclass(frozen=True)
class Frame:
    """One FITS file of the night: where, when (Unix s) and what its header says."""

    name: str
    start: float
    exposure_time: float
    image_type: str
    filter_name: str
    task: str
    guide_rms: float | None
    focus: float | None

    @property
    def end(self) -> float:
        return self.start + self.exposure_time

    @property
    def light(self) -> bool:
        """Light reaches the chip (not a bias or dark)."""
        return self.image_type not in ("bias", "dark")


@dataclass(frozen=True)
class TaskRun:
    """A task from its start to its end; ``outcome`` is done, failed or running (no end seen)."""

    task_id: str
    name: str
    start: float
    end: float | None
    outcome: str
    reason: str = ""


@dataclass
class Night:
    """Everything the report needs."""

    records: list[Record] = field(default_factory=list)
    frames: list[Frame] = field(default_factory=list)

    def of(self, *kinds: str) -> list[Record]:
        return [r for r in self.records if r.kind in kinds]

    @property
    def span(self) -> Interval:
        """First and last recorded clock time."""
        if not self.records:
            return (0.0, 0.0)
        return (self.records[0].t, self.records[-1].t)


def read_night(out_dir: Path, events: str = "events.jsonl", frames: str = "frames") -> Night:
    """The records of ``out_dir/events`` and the headers of the FITS files in ``out_dir/frames``."""
    from astropy.io import fits  # type: ignore[import-untyped]

    night = Night()
    path = out_dir / events
    if path.is_file():
        for line in path.read_text(encoding="utf-8").splitlines():
            if line.strip():
                raw = json.loads(line)
                night.records.append(Record(float(raw["t"]), raw["kind"], raw.get("sender", ""), raw["data"]))
    for fits_path in sorted((out_dir / frames).glob("*.fits")):
        header = fits.getheader(fits_path)
        night.frames.append(frame_of_header(fits_path.name, dict(header)))
    night.frames.sort(key=lambda f: f.start)
    return night


def frame_of_header(name: str, header: dict[str, Any]) -> Frame:
    """The frame a FITS header describes (DATE-OBS in UTC)."""
    rms = header.get("GUIDRMS")
    focus = header.get("FOCUS")
    return Frame(
        name=name,
        start=parse_time(str(header["DATE-OBS"])),
        exposure_time=float(header.get("EXPTIME", 0.0)),
        image_type=str(header.get("IMAGETYP", "")).lower(),
        filter_name=str(header.get("FILTER", "")),
        task=str(header.get("TASK-NAM", "")),
        guide_rms=float(rms) if isinstance(rms, int | float) else None,
        focus=float(focus) if isinstance(focus, int | float) else None,
    )


#: How a night's frames are told apart, by IMAGETYP: those the observing is for, and those that
#: only serve it (written, but not announced with a NewImageEvent).
FRAME_KINDS: tuple[tuple[str, frozenset[str]], ...] = (
    ("science and calibration", frozenset({"object", "bias", "dark", "skyflat", "domeflat"})),
    ("focus and acquisition", frozenset({"focus", "acquisition"})),
)


def describe_frames(frames: Sequence[Frame]) -> str:
    """``225 frames (207 science and calibration, 18 focus and acquisition)``: the frames written,
    by :data:`FRAME_KINDS`; any other IMAGETYP is named on its own (``3 guiding``)."""
    parts = [f"{sum(1 for f in frames if f.image_type in types)} {kind}" for kind, types in FRAME_KINDS]
    known = frozenset().union(*(types for _, types in FRAME_KINDS))
    others = sorted({f.image_type for f in frames} - known)
    parts += [f"{sum(1 for f in frames if f.image_type == t)} {t or 'without IMAGETYP'}" for t in others]
    return f"{len(frames)} frames ({', '.join(parts)})"


def parse_time(text: str) -> float:
    """Unix seconds of an ISO time; without a zone it is UTC (as in FITS)."""
    moment = datetime.fromisoformat(text)
    if moment.tzinfo is None:
        moment = moment.replace(tzinfo=UTC)
    return moment.timestamp()


def roof_open_intervals(records: Sequence[Record], end: float) -> list[Interval]:
    """When the roof was open: from RoofOpenedEvent to the next RoofClosingEvent (or ``end``)."""
    return _intervals(records, ("RoofOpenedEvent",), ("RoofClosingEvent", "RoofClosedEvent"), end)


def bad_weather_intervals(records: Sequence[Record], end: float) -> list[Interval]:
    """When the weather was bad: BadWeatherEvent to the time the next GoodWeatherEvent names.

    Until the first weather event the weather counts as unknown, i.e. bad (as the mastermind
    sees it).
    """
    intervals: list[Interval] = []
    bad_since: float | None = records[0].t if records else None
    for record in records:
        if record.kind == "BadWeatherEvent" and bad_since is None:
            bad_since = record.t
        elif record.kind == "GoodWeatherEvent" and bad_since is not None:
            eta = record.data.get("eta")
            good_from = max(record.t, parse_time(eta)) if eta else record.t
            if good_from > bad_since:
                intervals.append((bad_since, good_from))
            bad_since = None
    if bad_since is not None:
        intervals.append((bad_since, end))
    return intervals


def _intervals(
    records: Iterable[Record], opening: tuple[str, ...], closing: tuple[str, ...], end: float
) -> list[Interval]:
    intervals: list[Interval] = []
    since: float | None = None
    for record in records:
        if record.kind in opening and since is None:
            since = record.t
        elif record.kind in closing and since is not None:
            intervals.append((since, record.t))
            since = None
    if since is not None:
        intervals.append((since, end))
    return intervals


def task_runs(records: Sequence[Record]) -> list[TaskRun]:
    """Every task started, with how it ended (TaskFinishedEvent, TaskFailedEvent with its reason)."""
    runs: list[TaskRun] = []
    open_runs: dict[str, int] = {}
    for record in records:
        task_id = str(record.data.get("id", ""))
        if record.kind == "TaskStartedEvent":
            open_runs[task_id] = len(runs)
            runs.append(TaskRun(task_id, str(record.data.get("name", "")), record.t, None, "running"))
        elif record.kind in ("TaskFinishedEvent", "TaskFailedEvent") and task_id in open_runs:
            run = runs[open_runs.pop(task_id)]
            done = record.kind == "TaskFinishedEvent"
            runs[runs.index(run)] = TaskRun(
                run.task_id,
                run.name,
                run.start,
                record.t,
                "done" if done else "failed",
                "" if done else str(record.data.get("reason", "")),
            )
    return runs
