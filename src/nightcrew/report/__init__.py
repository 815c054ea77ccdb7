"""The night report: ``report.html`` made from a night's records (events.jsonl) and frames.

``nightcrew sim`` writes it at the end of the night, ``nightcrew report OUT_DIR`` again from the
files. The data extraction (:mod:`nightcrew.report._data`) and the numbers
(:mod:`nightcrew.report._metrics`) are pure; the charts are hand-written SVG.
"""

from nightcrew.report._data import Frame, Night, Record, TaskRun, read_night
from nightcrew.report._metrics import NightNumbers, night_numbers
from nightcrew.report._write import NIGHT_RECORD, REPORT_FILE, night_site, write_report

__all__ = [
    "NIGHT_RECORD",
    "REPORT_FILE",
    "Frame",
    "Night",
    "NightNumbers",
    "Record",
    "TaskRun",
    "night_numbers",
    "night_site",
    "read_night",
    "write_report",
]
