"""Reducing a night of raw frames: masters, calibration, detection, plate solving, catalogs.

:func:`reduce_night` does the work (see :mod:`._night` for the output layout and re-runs);
``nightcrew reduce RAW_DIR OUT_DIR`` is its command line. :func:`reduce_frame` reduces one science
frame; the online ``Pipeline`` module uses it too.
"""

from nightcrew.images.reduce._frame import REDUCED_LEVEL, Master, ReductionSteps, StageTimes, reduce_frame
from nightcrew.images.reduce._inventory import FrameEntry, GroupKey, frame_role, group_frames, read_entry
from nightcrew.images.reduce._night import ReduceOptions, find_raw_frames, reduce_night
from nightcrew.images.reduce._summary import (
    SUMMARY_NAME,
    ProgressBar,
    SummaryRow,
    read_summary,
    write_summary,
)

__all__ = [
    "REDUCED_LEVEL",
    "SUMMARY_NAME",
    "FrameEntry",
    "GroupKey",
    "Master",
    "ProgressBar",
    "ReduceOptions",
    "ReductionSteps",
    "StageTimes",
    "SummaryRow",
    "find_raw_frames",
    "frame_role",
    "group_frames",
    "read_entry",
    "read_summary",
    "reduce_frame",
    "reduce_night",
    "write_summary",
]
