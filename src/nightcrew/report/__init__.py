"""The night report: ``report.html`` made from a night's records (events.jsonl) and frames.

``nightcrew sim`` writes it at the end of the night, ``nightcrew report OUT_DIR`` again from the
files. The data extraction (:mod:`nightcrew.report._data`), the numbers
(:mod:`nightcrew.report._metrics`) and where the dark time went
(:mod:`nightcrew.report._time_budget`) are pure; the charts are hand-written SVG.
"""

from nightcrew.report._data import FRAME_KINDS, Frame, Night, Record, TaskRun, describe_frames, read_night
from nightcrew.report._metrics import NightNumbers, night_numbers
from nightcrew.report._season import (
    SeasonNight,
    season_night,
    season_night_from,
    season_row,
    season_summary,
    season_table,
)
from nightcrew.report._time_budget import Acquisition, acquisitions, time_budget
from nightcrew.report._write import NIGHT_RECORD, REPORT_FILE, night_site, write_report

__all__ = [
    "FRAME_KINDS",
    "NIGHT_RECORD",
    "REPORT_FILE",
    "Acquisition",
    "Frame",
    "Night",
    "NightNumbers",
    "Record",
    "SeasonNight",
    "TaskRun",
    "acquisitions",
    "describe_frames",
    "night_numbers",
    "night_site",
    "read_night",
    "season_night",
    "season_night_from",
    "season_row",
    "season_summary",
    "season_table",
    "time_budget",
    "write_report",
]
