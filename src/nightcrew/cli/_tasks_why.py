"""``nightcrew tasks why ID``: when a task is planned in a night, or why not, from the database alone.

The site is ``--site FILE`` (a site YAML file as in the observatory directories), else
``$NIGHTCREW_SITE``, else ``site.yaml`` or ``shared/site.yaml`` in the current directory (the
observatory directory). The night is the one beginning on the evening of ``--night DATE`` at the
site, planned whole; without ``--night`` the night going on now (planned from now) or the next one.
The scheduler's settings are its defaults (``--step``, ``--slew-overhead``, ``--max-sun-altitude``
change them; give the values of your scheduler's module file for the same answer).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
from collections.abc import Callable
from datetime import UTC, date, datetime
from pathlib import Path
from typing import Any

from nightcrew.astro import local_noon
from nightcrew.config import load_data_file
from nightcrew.errors import ConfigError
from nightcrew.robotic.archives import SqliteTaskArchive
from nightcrew.robotic.tasks import SCHEDULABLE_STATES
from nightcrew.site import Site

__all__ = ["SITE_FILES", "add_why_parser", "load_site"]

#: Where ``tasks why`` looks for the site without --site and $NIGHTCREW_SITE, in this order.
SITE_FILES = ("site.yaml", "shared/site.yaml")


def add_why_parser(
    actions: Any,
    db: argparse.ArgumentParser,
    run: Callable[[Any], Any],
    database_path: Callable[[argparse.Namespace], Path],
) -> None:
    """The ``why`` action (``db``: the --db option's parser, ``run``: wraps the coroutine,
    ``database_path``: the database the arguments name)."""
    why = actions.add_parser(
        "why", parents=[db], help="when a task is planned in a night, or why not", description=__doc__
    )
    why.add_argument("task_id", metavar="ID")
    why.add_argument(
        "--night", type=date.fromisoformat, metavar="DATE", help="the night from this evening on"
    )
    why.add_argument("--site", type=Path, metavar="FILE", help="site YAML file (default: see above)")
    why.add_argument("--step", type=float, default=300.0, help="time slice, seconds (default 300)")
    why.add_argument("--slew-overhead", type=float, default=100.0, help="per block, seconds (default 100)")
    why.add_argument(
        "--max-sun-altitude", type=float, default=-12.0, help="the night's Sun limit, degrees (default -12)"
    )
    why.set_defaults(func=run(_why), database_path=database_path)


async def _why(args: argparse.Namespace) -> int:
    # Imported here: the scheduler brings scipy, which every other ``nightcrew tasks`` command
    # would load for nothing (they are run in loops by scripts and tests).
    from nightcrew.robotic.scheduler import Scheduler
    from nightcrew.robotic.scheduler.ports import night_around
    from nightcrew.robotic.tasks.why import why_not_planned

    site = load_site(args.site)
    path = args.database_path(args)
    async with SqliteTaskArchive(path, poll_interval=0) as archive:
        task = await archive.get_task(args.task_id)  # an unknown id: one line, exit 1
        tasks = await archive.list_tasks(states=SCHEDULABLE_STATES)
    now = datetime.now(UTC)
    start = now if args.night is None else datetime.fromtimestamp(local_noon(args.night, site.longitude), UTC)
    night = night_around(site, start, max_sun_altitude=args.max_sun_altitude)
    scheduler = Scheduler(step_s=args.step, slew_overhead_s=args.slew_overhead)
    answer = why_not_planned(task, tasks, night, scheduler, now=now if args.night is None else None)
    print(
        f"task {task.id} ({task.name}), night {night.start:%Y-%m-%d %H:%M} - {night.end:%H:%M} UTC: {answer}"
    )
    return 0


def load_site(path: Path | None) -> Site:
    """The site from ``path``, $NIGHTCREW_SITE or the first of :data:`SITE_FILES` that exists."""
    if path is None and os.environ.get("NIGHTCREW_SITE"):
        path = Path(os.environ["NIGHTCREW_SITE"])
    if path is None:
        path = next((Path(name) for name in SITE_FILES if Path(name).is_file()), None)
    if path is None:
        raise ConfigError(
            f"no site: give --site FILE or set NIGHTCREW_SITE (none of {', '.join(SITE_FILES)} here)"
        )
    data = load_data_file(path)
    if not isinstance(data, dict):
        raise ConfigError(f"{path}: a site file is a mapping with latitude, longitude and elevation")
    fields = {f.name for f in dataclasses.fields(Site)}
    try:
        return Site(**{key: value for key, value in data.items() if key in fields})
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"{path}: {exc}") from None
