"""The night's recorder: every event on the bus, one JSON line each, for the night report.

Each line is ``{"t": clock unix time, "kind": event name, "sender": module, "data": fields}``.
Some events are worth more than they carry: after a FocusFoundEvent or FocusFailedEvent the
recorder asks the focus module for its series (``FocusSeries`` line: positions and widths, and
``failed`` with the reason), which the event leaves out.
Other parts of the night may add their own lines with :meth:`EventRecorder.record` (the driver
records the scheduler's plans that way). Lines are flushed at once: a crashed night still leaves
its record.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path
from typing import IO, Any

from nightcrew.config import DataPath
from nightcrew.errors import NightcrewError
from nightcrew.events import Event, FocusFailedEvent, FocusFoundEvent, event_by_name
from nightcrew.events.base import event_names
from nightcrew.interfaces import IAutoFocus, ModuleState
from nightcrew.modules.module import Module
from nightcrew.report.records import FOCUS_SERIES, NIGHT_RECORD, SCHEDULE_RECORD

__all__ = ["FOCUS_SERIES", "NIGHT_RECORD", "SCHEDULE_RECORD", "EventRecorder"]

log = logging.getLogger(__name__)


class EventRecorder(Module):
    """Writes every event it hears to a JSON-lines file.

    Args:
        path: The file (a local path; ``nightcrew sim`` puts it into ``--out``).
        **kwargs: Module options.
    """

    def __init__(self, *, path: DataPath = "events.jsonl", **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self._path = Path(path)
        self._file: IO[str] | None = None

    async def open(self) -> None:
        if self.state is not ModuleState.STARTING:
            return
        self._path.parent.mkdir(parents=True, exist_ok=True)
        self._file = self._path.open("w", encoding="utf-8")
        await super().open()
        for name in event_names():
            event_type = event_by_name(name)
            if event_type is not None and event_type is not Event:
                await self.comm.register_event(event_type, self.on_event)

    async def close(self) -> None:
        await super().close()
        if self._file is not None:
            self._file.close()
            self._file = None

    async def on_event(self, event: Event, sender: str) -> None:
        self.record(event.event_name(), event.to_dict(), sender=sender)
        if isinstance(event, FocusFoundEvent | FocusFailedEvent):
            await self._record_focus_series(sender)

    def record(self, kind: str, data: dict[str, Any], *, sender: str | None = None) -> None:
        """Add one line of ``kind`` with ``data`` (JSON values) at the current clock time."""
        if self._file is None:
            return
        line = {"t": round(self.clock.time(), 3), "kind": kind, "sender": sender or self.name, "data": data}
        self._file.write(json.dumps(line, default=str) + "\n")
        self._file.flush()

    async def _record_focus_series(self, sender: str) -> None:
        try:
            status = await (await self.proxy(sender, IAutoFocus)).auto_focus_status()
        except NightcrewError as exc:
            log.warning("%s: no focus series from %s: %s", self.name, sender, exc)
            return
        self.record(FOCUS_SERIES, status, sender=sender)
