"""The robotic night of ``nightcrew sim`` (see :mod:`nightcrew.cli.sim` for the options).

One engine runs every night: the scheduler plans, the mastermind runs. What differs between the
whole night, ``--quick`` and each night of a season (``--nights``) is only the span, the task
list and the weather, which :func:`night_setup` decides.
"""

from __future__ import annotations

import asyncio
import json
import sys
import time
from dataclasses import dataclass
from datetime import UTC, date, datetime, timedelta
from pathlib import Path
from typing import Any, TextIO

from nightcrew.clock import AcceleratedClock, Clock, VirtualClock
from nightcrew.errors import ConfigError
from nightcrew.night.build import (
    bundled_observatory,
    files_environ,
    load_in_process,
    observatory_site,
)
from nightcrew.night.cadences import stored_cadences
from nightcrew.night.engine import (
    TASKS_FILE,
    NightProgress,
    ProgressCallback,
    WholeNight,
    night_tasks,
    run_whole_night,
)
from nightcrew.night.fields import choose_targets, night_start, quick_groups
from nightcrew.night.options import SimOptions
from nightcrew.night.plan import night_span, weather_scenario
from nightcrew.night.running import quiet_module_logs, stop_on_signals
from nightcrew.night.sky_indexes import build_night_sky_indexes
from nightcrew.report import describe_frames, read_night, write_report
from nightcrew.robotic.tasks import RequestGroup
from nightcrew.site import Site

__all__ = [
    "NIGHT_CAMERA_PX",
    "QUICK_HOURS",
    "WALL_TIME_FILE",
    "NightSetup",
    "night_setup",
    "night_speed",
    "run_night",
    "run_one_night",
    "sim_clock",
]

#: Where the wall time of a run went (the one file in --out that differs from run to run).
WALL_TIME_FILE = "wall-time.json"

#: The camera of the whole night renders a quarter of the chip (1024 x 1024 px at 1.16"/px, a
#: 20' field; camera.yaml reads it from $SIM_CHIP_PX): every frame is still rendered and written,
#: four times faster and smaller.
NIGHT_CAMERA_PX = 1024

#: Clock seconds per wall second of a night watched live without ``--speed``: the quick night, and
#: the whole night (14.4 h in under 3 minutes).
QUICK_WATCH_SPEED, NIGHT_WATCH_SPEED = 60.0, 320.0

#: Clock hours of a ``--quick`` night without ``--hours``.
QUICK_HOURS = 1.0


@dataclass(frozen=True)
class NightSetup:
    """What one night runs: its span, its tasks (None: the samples and the survey), its weather."""

    night: date
    start: datetime
    end: datetime
    tasks: list[RequestGroup] | None
    weather: str


def run_night(options: SimOptions) -> int:
    directory: Path = options.configs or bundled_observatory()
    site = observatory_site(directory)
    setup = night_setup(options, site, options.date)
    if options.archive:
        from nightcrew.night.archive import clear_archive_products

        clear_archive_products(options.out)
    with quiet_module_logs(options.show_logs):
        result, wall = run_one_night(directory, options, site, setup, options.out, _printer(sys.stderr))
    # The files the night wrote, not the NewImageEvents: focus and acquisition frames are not announced.
    recorded = read_night(options.out)
    report = write_report(options.out, night=recorded, cadences=stored_cadences(options.out / TASKS_FILE))
    pace = describe_pace(night_speed(options))
    state = "night complete" if result.completed else "night stopped early"
    print(
        f"{state}: {describe_frames(recorded.frames)}, {result.tasks_started} tasks started, "
        f"weather {setup.weather} "
        f"(night of {setup.night}, {setup.start:%H:%M}-{setup.end:%H:%M} UTC {pace}; "
        f"{wall:.1f} s wall time)"
    )
    print(f"  frames, events.jsonl, tasks.sqlite in {options.out}")
    print(f"  night report: {report}")
    if options.archive:
        from nightcrew.night.archive import archive_and_show

        with quiet_module_logs(options.show_logs):
            archived = archive_and_show(options.out)
        if not archived:
            return 1
    return 0 if result.completed else 130


def night_setup(options: SimOptions, site: Site, night: date) -> NightSetup:
    """The span, tasks and weather of ``night`` under the command's options."""
    if options.quick:
        start = end = night_start(night, site)
    else:
        try:
            start, end = night_span(night, site)
        except ValueError as exc:
            raise ConfigError(f"night of {night}: {exc}") from exc
    if options.start is not None:
        day = night if options.start.hour >= 12 else night + timedelta(days=1)
        start = datetime.combine(day, options.start, tzinfo=UTC)
        if not options.quick and not start < end:
            raise ConfigError(f"--start {options.start:%H:%M} is after dawn ({end:%H:%M} UTC)")
    if options.quick:
        end = start + timedelta(hours=options.hours or QUICK_HOURS)
    elif options.hours is not None:
        end = min(end, start + timedelta(hours=options.hours))
    tasks = _quick_tasks(options, site, start, end) if options.quick else None
    weather = options.weather or ("clear" if options.quick else "interruption")
    return NightSetup(night=night, start=start, end=end, tasks=tasks, weather=weather)


def _quick_tasks(options: SimOptions, site: Site, start: datetime, end: datetime) -> list[RequestGroup]:
    filters = [name.strip() for name in options.filters.split(",") if name.strip()]
    if not filters:
        raise ConfigError(f"--filters {options.filters!r}: name at least one filter")
    wheel = (options.configs or bundled_observatory()) / "filters.yaml"
    config = load_in_process(wheel) if wheel.is_file() else {}
    known = [str(name) for name in config.get("filters", [])]
    unknown = [name for name in filters if known and name not in known]
    if unknown:
        # Said before the night starts, not as a task failing at the telescope.
        raise ConfigError(f"--filters: unknown filter {unknown[0]!r}; known filters: {', '.join(known)}")
    try:
        targets = choose_targets(site, start.timestamp(), options.targets)
    except ValueError as exc:
        raise ConfigError(f"--date {options.date}: {exc}") from exc
    return quick_groups(
        targets,
        filters,
        options.exposure_time,
        start=start,
        end=end,
        calibration_frames=options.calibration_frames,
    )


def run_one_night(
    directory: Path,
    options: SimOptions,
    site: Site,
    setup: NightSetup,
    out: Path,
    progress: ProgressCallback | None,
    *,
    seed: int | None = None,
) -> tuple[WholeNight, float]:
    """Run ``setup`` on the observatory of ``directory`` into ``out``; the result and wall seconds.

    ``seed`` (default ``--seed``) seeds the devices, the weather among them.
    """
    seed = options.seed if seed is None else seed
    duration = (setup.end - setup.start).total_seconds()
    # --quick keeps the full chip: its few frames then span 40', which solve-field's Tycho-2 index solves.
    devices = _device_overrides(setup.weather, duration, seed)
    clock = sim_clock(setup.start, night_speed(options))
    extras, environ = _extras(options)
    environ.update(_night_environ(seed, quarter_chip=setup.tasks is None))
    tasks = setup.tasks if setup.tasks is not None else night_tasks(setup.night, site)
    # The solvers' index files of the simulated sky, for the night's fields (kept for later nights);
    # the observatory's files find them by $SIM_SEED.
    build_night_sky_indexes(
        directory, tasks, environ={**files_environ(), **environ}, seed=seed, progress=_index_progress
    )
    wall_start, cpu_start = time.monotonic(), time.process_time()

    async def night() -> WholeNight:
        async with stop_on_signals() as stop:
            return await run_whole_night(
                directory,
                night=setup.night,
                site=site,
                clock=clock,
                end=setup.end,
                out_dir=out,
                device_overrides=devices,
                seed=seed,
                tasks=tasks,
                progress=progress,
                stop=stop,
                extras=extras,
                environ=environ,
            )

    try:
        result = asyncio.run(night())
    finally:
        if progress is not None and sys.stderr.isatty():
            sys.stderr.write("\n")  # end the rewritten progress line
    wall = time.monotonic() - wall_start
    _write_wall_time(out / WALL_TIME_FILE, clock, wall, time.process_time() - cpu_start)
    return result, wall


def night_speed(options: SimOptions) -> float | None:
    """``--speed``; None: the virtual clock. A night watched live (``--indi``, ``--console``) runs
    an accelerated clock by default, as a virtual one would be over before a client looked."""
    speed: float | None = options.speed
    if speed is not None or (options.indi is None and options.console is None):
        return speed
    return QUICK_WATCH_SPEED if options.quick else NIGHT_WATCH_SPEED


def sim_clock(start: datetime, speed: float | None) -> Clock:
    """The simulation's clock: virtual (repeatable, as fast as the machine allows), or with
    ``speed`` an accelerated one."""
    return VirtualClock(start) if speed is None else AcceleratedClock(start, speed=speed)


def describe_pace(speed: float | None) -> str:
    return "on virtual time" if speed is None else f"at {speed:g}x"


def _device_overrides(weather: str, duration: float, seed: int | None) -> dict[str, dict[str, Any]]:
    """The weather station's scenario for the night (made from ``weather`` and the night's length)."""
    station: dict[str, Any] = {"scenario": weather_scenario(weather, duration), "duration": duration + 3600}
    if seed is not None:
        station["seed"] = seed
    return {"conditions": station}


def _night_environ(seed: int | None, *, quarter_chip: bool) -> dict[str, str]:
    """The variables the observatory's files read for a night: the camera's chip (a whole night
    reads out a quarter of it, :data:`NIGHT_CAMERA_PX`) and, with ``seed``, the seed the
    acquisition's catalog follows (the camera's synthetic stars)."""
    environ = {"SIM_CHIP_PX": str(NIGHT_CAMERA_PX)} if quarter_chip else {}
    if seed is not None:
        environ["SIM_SEED"] = str(seed)
    return environ


def _index_progress(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _write_wall_time(path: Path, clock: Clock, wall: float, cpu: float) -> None:
    """Wall and CPU seconds of the run and, on a virtual clock, what the loop waited on."""
    waited = clock.wall_waited() if isinstance(clock, VirtualClock) else {}
    record = {"wall_s": round(wall, 3), "cpu_s": round(cpu, 3), "waited_s": waited}
    path.write_text(json.dumps(record, indent=1) + "\n", encoding="utf-8")


def _extras(options: SimOptions) -> tuple[list[str], dict[str, str]]:
    """The option files the options ask for (options/indi.yaml, console.yaml, pipeline.yaml) and
    the variables they read."""
    extras, environ = [], {}
    if options.indi is not None:
        extras.append("indi")
        environ["SIM_INDI_PORT"] = str(options.indi)
    if options.console is not None:
        extras.append("console")
        environ["SIM_CONSOLE_PORT"] = str(options.console)
    if options.archive:
        extras.append("pipeline")
    return extras, environ


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
