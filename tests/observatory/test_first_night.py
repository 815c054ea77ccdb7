"""The first night of an observatory written by ``nightcrew init``, on alpaca-simulators and Prosody,
driven only through the command line as docs/observatory.md tells a user (issue 25, first Done-when).

``nightcrew init --non-interactive`` → ``nightcrew server init/start`` → ``nightcrew check`` →
``nightcrew up`` → three targets with ``nightcrew tasks add`` → the dome opens, science frames with
full headers are written, the camera module is killed (kill -9 by PID) mid-task and the night goes
on without dropping a task → ``nightcrew up`` is stopped: the dome closes and the telescope parks.

Real time on the simulators: the site's longitude puts the moment the test runs at 22:00 local mean
time at latitude 30° (the Sun at least 25° below the horizon in every season, and still setting, so
the mastermind sees night, not dawn), the targets are near the zenith, exposures are 2 s, and the weather
verdict needs no settling time (``--good-weather-after 0``). Without alpaca-simulators or Prosody the
test skips, except under CI=true.
"""

from __future__ import annotations

import json
import os
import signal
import time
import urllib.request
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path

import pytest
from astropy.io import fits  # type: ignore[import-untyped]

from nightcrew.astro import local_sidereal_time
from nightcrew.testing.alpaca import AlpacaSimulator
from tests.comm.xmpp_servers import require_command

from .night import LATITUDE, evening_longitude, running_observatory, task_file, wait
from .simulators import run_alpaca_simulators

pytestmark = pytest.mark.xmpp
NIGHT_TIMEOUT = 900.0  # wall seconds for the whole night on a busy machine (a few minutes when idle)
SCIENCE_HEADERS = {"DATE-OBS", "EXPTIME", "IMAGETYP", "FILTER", "RA", "DEC", "AIRMASS", "TEL-ALT", "FOCUS"}


@pytest.fixture
def night_simulator(tmp_path: Path) -> Iterator[AlpacaSimulator]:
    require_command("prosody", "prosody")
    longitude = evening_longitude(datetime.now(UTC))
    yield from run_alpaca_simulators(tmp_path / "alpaca-sim", latitude=LATITUDE, longitude=longitude)


def device(simulator: AlpacaSimulator, path: str) -> object:
    with urllib.request.urlopen(
        f"{simulator.url}/api/v1/{path}?ClientID=1&ClientTransactionID=1", timeout=10
    ) as r:
        return json.loads(r.read())["Value"]


@pytest.mark.timeout(1200)  # a night in real time (a few minutes when idle)
def test_first_night_on_alpaca_simulators(night_simulator: AlpacaSimulator, tmp_path: Path) -> None:
    now = datetime.now(UTC)
    longitude = evening_longitude(now)
    deadline = time.monotonic() + NIGHT_TIMEOUT
    devices = ["--alpaca", night_simulator.url]
    with running_observatory(tmp_path, devices, longitude, deadline, "--elevation", "1000") as night:
        # Three targets near the zenith: the local sidereal time is the right ascension overhead.
        lst = float(local_sidereal_time(now.timestamp(), longitude))
        for number, (offset, filter_name) in enumerate(((-15.0, "Red"), (0.0, "Green"), (15.0, "Blue")), 1):
            task_file(
                night.directory / f"target{number}.yaml",
                f"field {number}",
                (lst + offset) % 360,
                LATITUDE,
                filter_name,
            )
        night("tasks", "--db", "tasks.sqlite", "add", "target1.yaml", "target2.yaml", "target3.yaml")
        assert len(night.tasks()) == 3  # stored (and perhaps planned already)

        wait(lambda: device(night_simulator, "dome/0/shutterstatus") == 0, deadline, "the dome to open")
        wait(lambda: len(night.science_frames()) >= 1, deadline, "the first science frame")
        camera_pid = int(night.status()["camera"][2])
        os.kill(camera_pid, signal.SIGKILL)  # mid-task: the first target has frames still to take
        wait(
            lambda: night.status()["camera"][2] not in ("-", str(camera_pid)),
            deadline,
            "the camera's restart",
        )
        wait(lambda: set(night.tasks().values()) == {"COMPLETED"}, deadline, "every task done")
        frames = night.science_frames()
        assert len(frames) >= 6
        for frame in frames:
            header = fits.getheader(frame)
            assert set(header) >= SCIENCE_HEADERS, (frame.name, SCIENCE_HEADERS - set(header))
            assert header["IMAGETYP"].lower() == "object" and header["EXPTIME"] == pytest.approx(2.0)
    assert device(night_simulator, "dome/0/shutterstatus") == 1  # closed
    assert device(night_simulator, "telescope/0/atpark") is True
