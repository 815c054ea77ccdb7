"""What the first-night tests share: the site where it is night now, task files, the command line."""

from __future__ import annotations

import contextlib
import json
import os
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from datetime import UTC, datetime, timedelta
from pathlib import Path

from nightcrew.server import stop_server
from nightcrew.testing.processes import free_port

__all__ = ["LATITUDE", "Night", "evening_longitude", "running_observatory", "task_file", "wait"]

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


@contextlib.contextmanager
def running_observatory(
    tmp_path: Path, devices: list[str], longitude: float, deadline: float, *init_options: str
) -> Iterator[Night]:
    """As docs/observatory.md tells a user: ``nightcrew init --non-interactive`` (devices from
    ``devices``, e.g. ``["--alpaca", URL]``, the site at ``longitude``), ``server init/start``,
    ``check``, ``nightcrew up`` until the mastermind runs; on leaving, ``up`` is stopped by SIGTERM
    as systemd or Ctrl-C would (roof closed and mount parked first) and must end with 0."""
    directory = tmp_path / "observatory"
    environment = {
        **os.environ,
        "PATH": f"{Path(sys.executable).parent}:{os.environ['PATH']}",
        "NIGHTCREW_SUPERVISOR_SOCKET": str(tmp_path / "supervisor.sock"),
        "NIGHTCREW_COMM": "operator.yaml",
    }
    xmpp_port = free_port()
    night = Night(tmp_path, environment)
    night(
        "init", str(directory), "--non-interactive", *devices,
        "--latitude", str(LATITUDE), "--longitude", str(longitude), *init_options,
        "--xmpp-server", f"127.0.0.1:{xmpp_port}", "--console-port", str(free_port()),
        "--good-weather-after", "0",
    )  # fmt: skip
    night.directory = directory
    up: subprocess.Popen[bytes] | None = None
    try:
        yaml_files = sorted(p.name for p in directory.glob("*.yaml"))
        night("server", "init", "xmpp", "--port", str(xmpp_port), *yaml_files)
        night("server", "start", "xmpp")
        night("check", ".")
        with open(tmp_path / "up.log", "wb") as log:
            up = subprocess.Popen(
                [sys.executable, "-m", "nightcrew", "up", "."], cwd=directory, env=environment, stderr=log
            )
        wait(lambda: night.status().get("mastermind", ["", ""])[1] == "running", deadline, "the modules")
        yield night
    finally:
        if up is not None:
            up.send_signal(signal.SIGTERM)  # modules close: the roof first, the mount parks
            up.wait(timeout=120)
        if (directory / "xmpp" / "prosody.pid").exists():
            stop_server(directory / "xmpp")
    assert up is not None and up.returncode == 0
    # Closing parks and closes at the devices' own pace: no module may be killed halfway.
    assert "did not stop within" not in (tmp_path / "up.log").read_text()
