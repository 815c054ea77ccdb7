"""What ``nightcrew sim`` is asked for: one options object; the CLI only fills it in.

:func:`~nightcrew.night.run.run_sim` runs what the options ask for: a night (:mod:`.sim`), a season of nights
(:mod:`.season`) or the devices served to Alpaca clients (:mod:`.alpaca`). The observatory is the
directory of module files ``configs`` (the bundled ``examples/observatory`` by default), built
as :mod:`.build` says.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import date
from datetime import time as time_of_day
from pathlib import Path

__all__ = ["DEFAULT_NIGHT", "SimOptions"]

#: A moonless autumn night (new moon on 2026-11-09) with Cygnus and Cassiopeia high after dusk.
DEFAULT_NIGHT = date(2026, 11, 10)


@dataclass(frozen=True)
class SimOptions:
    """The options of ``nightcrew sim`` (``nightcrew sim --help`` says what each does).

    Attributes:
        out: Output directory: frames, events.jsonl, tasks.sqlite, report.html.
        date: The night (its evening's date).
        speed: Clock seconds per wall second of an accelerated clock; None: the virtual clock.
        seed: Replaces the seeds of all modules.
        weather: A weather scenario of :data:`~nightcrew.night.plan.WEATHER_SCENARIOS`; None: the
            default of the night's kind.
        start: UTC time to start at instead of dusk (before noon: the morning after ``date``).
        hours: Clock hours to stop after (None: at dawn; ``quick``: 1).
        nights: Consecutive nights from ``date`` (a season when > 1).
        frames: With ``nights`` > 1, keep every night's frames.
        quick: A short task list after dusk instead of the sample tasks.
        targets: ``quick``: number of star fields.
        filters: ``quick``: comma-separated filters, one exposure each.
        exposure_time: ``quick``: seconds per exposure.
        calibration_frames: ``quick``: biases and darks before the roof opens (0: none).
        configs: Directory of module files; None: the bundled one.
        indi: Also serve the devices to INDI clients on this loopback port.
        console: Serve the web console on this loopback port (0: a free one).
        archive: Reduce the night's object frames and archive everything at its end.
        show_logs: Show the modules' log messages.
        alpaca: Instead of a night, serve the devices as ASCOM Alpaca devices on this port.
        alpaca_discovery_port: The Alpaca discovery UDP port.
    """

    out: Path = Path("sim-output")
    date: date = DEFAULT_NIGHT
    speed: float | None = None
    seed: int | None = None
    weather: str | None = None
    start: time_of_day | None = None
    hours: float | None = None
    nights: int = 1
    frames: bool = False
    quick: bool = False
    targets: int = 3
    filters: str = "V,R"
    exposure_time: float = 30.0
    calibration_frames: int = 3
    configs: Path | None = None
    indi: int | None = None
    console: int | None = None
    archive: bool = False
    show_logs: bool = False
    alpaca: int | None = None
    alpaca_discovery_port: int = 32227
