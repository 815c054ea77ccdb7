"""``nightcrew sim --nights N``: a season of consecutive nights on the one engine, and its report.

Each night runs in ``--out/night-YYYY-MM-DD`` with its own seed (``--seed`` + night number, so
random weather differs from night to night and the season repeats), gets its report.html and
its row of numbers (also in its directory, ``season-row.json``, as soon as it is over); its
frames go afterwards unless ``--frames``. The season's table goes to
stdout and to ``--out/season.md``, all numbers to ``--out/season.json``.
"""

from __future__ import annotations

import json
import shutil
import sys
from datetime import timedelta
from pathlib import Path

from nightcrew.night.build import bundled_observatory, observatory_site
from nightcrew.night.engine import FRAMES
from nightcrew.night.options import SimOptions
from nightcrew.night.running import quiet_module_logs
from nightcrew.night.sim import night_setup, run_one_night
from nightcrew.report import (
    SeasonNight,
    describe_frames,
    read_night,
    season_night,
    season_row,
    season_summary,
    season_table,
    write_report,
)

__all__ = ["NIGHT_ROW", "SEASON_JSON", "SEASON_TABLE", "run_season"]

SEASON_TABLE = "season.md"
SEASON_JSON = "season.json"
#: Each night's row of the season, in its directory, written as soon as the night is over.
NIGHT_ROW = "season-row.json"


def run_season(options: SimOptions) -> int:
    directory: Path = options.configs or bundled_observatory()
    site = observatory_site(directory)
    base_seed = 0 if options.seed is None else options.seed
    rows: list[SeasonNight] = []
    wall_total = 0.0
    with quiet_module_logs(options.show_logs):
        for number in range(options.nights):
            night = options.date + timedelta(days=number)
            setup = night_setup(options, site, night)
            out = options.out / f"night-{night.isoformat()}"
            result, wall = run_one_night(directory, options, site, setup, out, None, seed=base_seed + number)
            wall_total += wall
            recorded = read_night(out)
            write_report(out, thumbnails=options.frames, night=recorded)
            rows.append(
                season_night(night.isoformat(), recorded, latitude=site.latitude, longitude=site.longitude)
            )
            row = rows[-1]
            (out / NIGHT_ROW).write_text(json.dumps(season_row(row), indent=1) + "\n", encoding="utf-8")
            if not options.frames:
                shutil.rmtree(out / FRAMES, ignore_errors=True)
            print(
                f"night {number + 1}/{options.nights} {night}: shutter {100 * row.shutter_fraction:.1f} % of "
                f"{row.good_dark_s / 3600:.2f} h good dark, {describe_frames(recorded.frames)} "
                f"({wall:.0f} s wall)",
                file=sys.stderr,
                flush=True,
            )
            if not result.completed:
                break
    table = season_table(rows)
    (options.out / SEASON_TABLE).write_text(table, encoding="utf-8")
    summary = {**season_summary(rows), "wall_s": round(wall_total, 1), "weather": options.weather}
    (options.out / SEASON_JSON).write_text(json.dumps(summary, indent=1) + "\n", encoding="utf-8")
    print(table, end="")
    print(f"season of {len(rows)} nights in {options.out} ({wall_total:.0f} s wall time)")
    return 0 if len(rows) == options.nights else 130
