"""The whole robotic night of ``nightcrew sim`` (see :mod:`nightcrew.cli.sim` for the options)."""

from __future__ import annotations

import argparse
import asyncio
import json
import logging
import signal
import sys
import time
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any, TextIO

from nightcrew.clock import Clock, VirtualClock
from nightcrew.errors import ConfigError
from nightcrew.night.build import bundled_observatory
from nightcrew.night.engine import NightProgress, ProgressCallback, WholeNight, run_whole_night
from nightcrew.night.plan import night_span, weather_scenario
from nightcrew.report import write_report
from nightcrew.site import Site

__all__ = ["NIGHT_CAMERA", "WALL_TIME_FILE", "run_whole_night_command"]

#: Where the wall time of a run went (the one file in --out that differs from run to run).
WALL_TIME_FILE = "wall-time.json"

#: The camera of the whole night renders a quarter of the chip (1024 x 1024 px at 1.16"/px, a
#: 20' field): every frame is still rendered and written, four times faster and smaller.
NIGHT_CAMERA: dict[str, Any] = {"chip_width": 1024, "chip_height": 1024}


def run_whole_night_command(args: argparse.Namespace) -> int:
    from nightcrew.cli.sim import describe_pace, site_of

    directory: Path = args.configs or bundled_observatory()
    site = site_of(directory)
    try:
        start, end = night_span(args.date, site)
    except ValueError as exc:
        raise ConfigError(f"--date {args.date}: {exc}") from exc
    if args.start is not None:
        day = args.date if args.start.hour >= 12 else args.date + timedelta(days=1)
        start = datetime.combine(day, args.start, tzinfo=UTC)
        if not start < end:
            raise ConfigError(f"--start {args.start:%H:%M} is after dawn ({end:%H:%M} UTC)")
    if args.hours is not None:
        end = min(end, start + timedelta(hours=args.hours))
    speed: float | None = args.speed
    duration = (end - start).total_seconds()
    overrides = _device_overrides(directory, args.weather, duration, args.seed)
    robotic = _robotic_overrides(directory, args.seed)

    quiet = not (args.verbose or args.debug)
    logger = logging.getLogger("nightcrew")
    old_level = logger.level
    if quiet:
        logger.setLevel(logging.WARNING)
    from nightcrew.cli.sim import sim_clock

    clock = sim_clock(start, speed)
    wall_start, cpu_start = time.monotonic(), time.process_time()
    try:
        night = _run(directory, args, site, clock, end, (overrides, robotic), _printer(sys.stderr))
        result = asyncio.run(night)
    finally:
        logger.setLevel(old_level)
        if sys.stderr.isatty():
            sys.stderr.write("\n")  # end the rewritten progress line
    wall = time.monotonic() - wall_start
    _write_wall_time(args.out / WALL_TIME_FILE, clock, wall, time.process_time() - cpu_start)
    report = write_report(args.out)
    state = "night complete" if result.completed else "night stopped early"
    print(
        f"{state}: {result.frames} frames, {result.tasks_started} tasks started, weather {args.weather} "
        f"(night of {args.date}, {start:%H:%M}-{end:%H:%M} UTC {describe_pace(speed)}; "
        f"{wall:.1f} s wall time)"
    )
    print(f"  frames, events.jsonl, tasks.sqlite in {args.out}")
    print(f"  night report: {report}")
    return 0 if result.completed else 130


def _device_overrides(
    directory: Path, weather: str, duration: float, seed: int | None
) -> dict[str, dict[str, Any]]:
    from nightcrew.config import load_config, to_plain

    camera = load_config(directory / "camera.yaml") if (directory / "camera.yaml").is_file() else {}
    detector = {**to_plain(camera.get("detector") or {}), **NIGHT_CAMERA}
    station: dict[str, Any] = {"scenario": weather_scenario(weather, duration), "duration": duration + 3600}
    if seed is not None:
        station["seed"] = seed
    # Start near the best focus (25 mm + the temperature's shift): the focus series then brackets it.
    return {"weather": station, "camera": {"detector": detector}, "focuser": {"focus": 25.0}}


def _robotic_overrides(directory: Path, seed: int | None) -> dict[str, dict[str, Any]]:
    """With ``seed``, the acquisition's catalog follows the camera's new synthetic stars."""
    from nightcrew.config import load_config, to_plain

    path = directory / "robotic" / "acquisition.yaml"
    if seed is None or not path.is_file():
        return {}
    pipeline = to_plain(load_config(path).get("pipeline") or {})
    for step in pipeline.get("steps", []):
        if isinstance(step, dict) and "catalog_seed" in step:
            step["catalog_seed"] = seed
    return {"acquisition": {"pipeline": pipeline}}


async def _run(
    directory: Path,
    args: argparse.Namespace,
    site: Site,
    clock: Clock,
    end: datetime,
    overrides: tuple[dict[str, dict[str, Any]], dict[str, dict[str, Any]]],
    progress: ProgressCallback,
) -> WholeNight:
    stop = asyncio.Event()
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, stop.set)
    try:
        return await run_whole_night(
            directory,
            night=args.date,
            site=site,
            clock=clock,
            end=end,
            out_dir=args.out,
            device_overrides=overrides[0],
            robotic_overrides=overrides[1],
            seed=args.seed,
            progress=progress,
            stop=stop,
        )
    finally:
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.remove_signal_handler(sig)


def _write_wall_time(path: Path, clock: Clock, wall: float, cpu: float) -> None:
    """Wall and CPU seconds of the run and, on a virtual clock, what the loop waited on."""
    waited = clock.wall_waited() if isinstance(clock, VirtualClock) else {}
    record = {"wall_s": round(wall, 3), "cpu_s": round(cpu, 3), "waited_s": waited}
    path.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")


def _printer(stream: TextIO) -> ProgressCallback:
    """Progress as one rewritten line on a terminal, a line per clock half-hour elsewhere."""
    tty = stream.isatty()
    last: list[int] = [-1]

    def show(p: NightProgress) -> None:
        done = round(20 * p.fraction)
        task = p.task or "-"
        line = (
            f"[{'#' * done}{'.' * (20 - done)}] {p.now:%H:%M} UTC  Sun {p.sun_altitude:+5.1f}°  "
            f"frames {p.frames:4d}  {task[:40]}"
        )
        if tty:
            stream.write("\r\033[K" + line)
        else:
            slot = (p.now.hour * 60 + p.now.minute) // 30
            if slot == last[0]:
                return
            last[0] = slot
            stream.write(line + "\n")
        stream.flush()

    return show
