"""Reducing a night of raw frames: masters, calibration, detection, plate solving, catalogs.

:func:`reduce_night` does the work (see :mod:`._night` for the output layout and re-runs);
``nightcrew reduce RAW_DIR OUT_DIR`` is its command line.
"""

from nightcrew.images.reduce._inventory import FrameEntry, GroupKey, frame_role, group_frames, read_entry
from nightcrew.images.reduce._night import ReduceOptions, reduce_night
from nightcrew.images.reduce._summary import (
    SUMMARY_NAME,
    ProgressBar,
    SummaryRow,
    read_summary,
    write_summary,
)

__all__ = [
    "SUMMARY_NAME",
    "FrameEntry",
    "GroupKey",
    "ProgressBar",
    "ReduceOptions",
    "SummaryRow",
    "frame_role",
    "group_frames",
    "read_entry",
    "read_summary",
    "reduce_night",
    "write_summary",
]
