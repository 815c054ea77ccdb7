"""The kinds of the lines the night's recorder adds to events.jsonl besides the events themselves.

They are the format the report reads, so they live here; the recorder
(:mod:`nightcrew.night.recorder`) writes them.
"""

from __future__ import annotations

__all__ = ["FOCUS_SERIES", "NIGHT_RECORD", "SCHEDULE_RECORD"]

#: The ``kind`` of the line with a focus series' measurements.
FOCUS_SERIES = "FocusSeries"
#: The ``kind`` of the line where the night says where and when it is (``site``, ``start``, ``end``).
NIGHT_RECORD = "Night"
#: The ``kind`` of the lines with a plan of the scheduler (objective, bound, slots).
SCHEDULE_RECORD = "Schedule"
