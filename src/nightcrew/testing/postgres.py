"""A private PostgreSQL cluster for tests: Debian's server in a temporary directory, on loopback.

:class:`PostgresCluster` runs ``initdb`` into a fresh temporary directory (trust authentication for one
superuser, ``nightcrew``) and then ``postgres`` in the foreground as a child process listening
on 127.0.0.1 and a free port, with its Unix socket in the same directory, so the PID we hold is the
server's own and it is stopped by that PID. PostgreSQL refuses to run as root: when the tests
run as root the server runs as Debian's ``postgres`` user (``setpriv``, which execs, so the PID
stays the server's) in a directory under /tmp that user owns (pytest's ``tmp_path`` of root is
closed to other users). The system's clusters are never touched.

``fsync=off`` by default: a test cluster need not survive a power cut, and writes get ~10x faster;
pass ``durable=True`` for measurements that should count the flushes (bench/archive.py).
"""

from __future__ import annotations

import contextlib
import os
import pwd
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

from nightcrew.testing.processes import end_process, free_port, wait_until_listening

__all__ = ["PostgresCluster", "postgres_missing"]

_BIN_DIRS = "/usr/lib/postgresql"
_SERVICE_USER = "postgres"
_STOP_TIMEOUT = 30.0
_READY_TIMEOUT = 60.0
SUPERUSER = "nightcrew"


def _bin_dir() -> Path | None:
    versions = sorted(Path(_BIN_DIRS).glob("*/bin/postgres"), key=lambda p: int(p.parent.parent.name))
    return versions[-1].parent if versions else None


def postgres_missing() -> str | None:
    """Why a test cluster cannot run here, or None; raises under CI=true, where it must run."""
    reason = None
    if _bin_dir() is None:
        reason = f"no PostgreSQL server under {_BIN_DIRS} (apt-get install postgresql; make system-deps)"
    elif os.geteuid() == 0 and shutil.which("setpriv") is None:
        reason = "setpriv is missing (util-linux) to run PostgreSQL as a non-root user"
    if reason is not None and os.environ.get("CI") == "true":
        raise RuntimeError(reason + " - CI must have it")
    return reason


class PostgresCluster:
    """A PostgreSQL server with its data in a temporary directory of its own (:attr:`directory`).

    Args:
        port: TCP port on 127.0.0.1; a free one by default.
        durable: Keep fsync on (off by default: faster, and a test cluster is thrown away).
    """

    def __init__(self, *, port: int | None = None, durable: bool = False) -> None:
        self.directory = Path(tempfile.mkdtemp(prefix="nightcrew-postgres-"))
        self.host = "127.0.0.1"
        self.port = port or free_port(self.host)
        self.durable = durable
        self._process: subprocess.Popen[bytes] | None = None
        self._counter = 0

    @property
    def pid(self) -> int | None:
        """The server's PID while it runs."""
        process = self._process
        return process.pid if process is not None and process.poll() is None else None

    def dsn(self, database: str = "postgres") -> str:
        """The URL to connect to ``database`` as the superuser (no password: trust on loopback)."""
        return f"postgresql://{SUPERUSER}@{self.host}:{self.port}/{database}"

    def _as_owner(self, command: list[str]) -> list[str]:
        if os.geteuid() != 0:
            return command
        return ["setpriv", f"--reuid={_SERVICE_USER}", f"--regid={_SERVICE_USER}", "--init-groups", *command]

    def start(self) -> None:
        """initdb (once) and start the server; return once it accepts connections."""
        if self.pid is not None:
            return
        bin_dir = _bin_dir()
        if bin_dir is None:
            raise RuntimeError(postgres_missing() or "PostgreSQL is missing")
        data = self.directory / "data"
        if os.geteuid() == 0:
            owner = pwd.getpwnam(_SERVICE_USER)
            os.chown(self.directory, owner.pw_uid, owner.pw_gid)
        if not data.exists():
            initdb = [str(bin_dir / "initdb"), "-D", str(data), "-U", SUPERUSER, "-A", "trust"]
            _run(self._as_owner([*initdb, "-E", "UTF8", "--locale=C", "--no-sync"]))
        log = self.directory / "postgres.log"
        settings = [
            f"listen_addresses={self.host}",
            f"port={self.port}",
            f"unix_socket_directories={self.directory}",
        ]
        if not self.durable:
            settings += ["fsync=off", "synchronous_commit=off", "full_page_writes=off"]
        command = [str(bin_dir / "postgres"), "-D", str(data)]
        for setting in settings:
            command += ["-c", setting]
        with open(log, "ab") as output:
            self._process = subprocess.Popen(
                self._as_owner(command), stdin=subprocess.DEVNULL, stdout=output, stderr=output
            )
        wait_until_listening(self._process, self.port, what="postgres", log=log)
        self._wait_until_ready(bin_dir / "pg_isready", log)

    def _wait_until_ready(self, pg_isready: Path, log: Path) -> None:
        """It listens before it accepts logins (``the database system is starting up``)."""
        deadline = time.monotonic() + _READY_TIMEOUT
        command = [str(pg_isready), "-q", "-h", self.host, "-p", str(self.port), "-U", SUPERUSER]
        while subprocess.run(command, check=False, timeout=_READY_TIMEOUT).returncode != 0:
            if time.monotonic() > deadline or self.pid is None:
                tail = log.read_text(errors="replace").strip().splitlines()[-5:]
                raise RuntimeError(f"postgres did not get ready on port {self.port}: " + " | ".join(tail))
            time.sleep(0.05)

    def stop(self) -> None:
        """Stop the server by its PID (fast shutdown: clients are disconnected at once)."""
        process, self._process = self._process, None
        if process is None or process.poll() is not None:
            return
        end_process(process, signal.SIGINT, timeout=_STOP_TIMEOUT)

    async def create_database(self, prefix: str = "test") -> str:
        """A new empty database; return its DSN."""
        import asyncpg  # type: ignore[import-untyped]

        self._counter += 1
        name = f"{prefix}_{os.getpid()}_{self._counter}"
        connection = await asyncpg.connect(self.dsn(), timeout=30)
        try:
            await connection.execute(f'CREATE DATABASE "{name}"')
        finally:
            await connection.close()
        return self.dsn(name)

    def remove(self) -> None:
        """Stop the server and delete its directory."""
        self.stop()
        with contextlib.suppress(FileNotFoundError):
            shutil.rmtree(self.directory)


def _run(command: list[str]) -> None:
    result = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed: {result.stderr.strip() or result.returncode}")
