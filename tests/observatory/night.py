"""What the first-night tests share: the site where it is night now, task files, the command line."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from collections.abc import Callable
from datetime import UTC, datetime, timedelta
from pathlib import Path

__all__ = ["LATITUDE", "Night", "evening_longitude", "task_file", "wait"]

#: With local time 22:00 the Sun is at least 25° below the horizon here in every season, and setting.
LATITUDE = 30.0


def evening_longitude(now: datetime) -> float:
    """The longitude (east, -180..180) where the mean local time is 22:00 at ``now``."""
    hours = now.hour + now.minute / 60 + now.second / 3600
    return round((15.0 * (22.0 - hours) + 180.0) % 360.0 - 180.0, 3)


def task_file(path: Path, name: str, ra: float, dec: float, filter_name: str, count: int = 3) -> None:
    """A request group observing (ra, dec) now: ``count`` 2-s frames through ``filter_name``."""
    now = datetime.now(UTC)
    window = {
        "start": (now - timedelta(minutes=10)).isoformat(),
        "end": (now + timedelta(hours=2)).isoformat(),
    }
    group = {
        "name": name,
        "proposal": "first-night",
        "requests": [
            {
                "location": {"telescope_class": "0m4"},
                "windows": [window],
                "configurations": [
                    {
                        "type": "EXPOSE",
                        "target": {"name": name, "ra": ra, "dec": dec},
                        "instrument_configs": [
                            {
                                "exposure_time": 2,
                                "exposure_count": count,
                                "optical_elements": {"filter": filter_name},
                            }
                        ],
                    }
                ],
            }
        ],
    }
    path.write_text(json.dumps(group))


class Night:
    """The command line in the observatory directory, as a user types it."""

    def __init__(self, directory: Path, environment: dict[str, str]) -> None:
        self.directory = directory
        self.environment = environment

    def __call__(self, *args: str, check: bool = True) -> str:
        done = subprocess.run(
            [sys.executable, "-m", "nightcrew", *args],
            cwd=self.directory,
            env=self.environment,
            capture_output=True,
            text=True,
            timeout=120,
            check=False,
        )
        assert not check or done.returncode == 0, f"nightcrew {' '.join(args)}: {done.stdout}{done.stderr}"
        return done.stdout

    def status(self) -> dict[str, list[str]]:
        shown = self("status", check=False)
        return {row.split()[0]: row.split() for row in shown.splitlines()[1:] if row.strip()}

    def tasks(self) -> dict[str, str]:
        shown = self("tasks", "--db", "tasks.sqlite", "list")
        return {row.split()[0]: row.split()[1] for row in shown.splitlines()[1:] if row.strip()}

    def science_frames(self) -> list[Path]:
        images = self.directory / "images"
        return sorted(images.glob("*-object-*.fits")) if images.is_dir() else []


def wait(condition: Callable[[], bool], deadline: float, what: str) -> None:
    while not condition():
        assert time.monotonic() < deadline, f"timed out waiting for {what}"
        time.sleep(1.0)  # polling the command line like a user; bounded by the deadline
