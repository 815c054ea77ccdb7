"""A private Samba server for tests: its own smb.conf, private directories, port and account.

:class:`SambaServer` writes ``smb.conf`` into one directory with every state, cache, lock and
private directory inside it, one share (``[files]``) on ``files/``, and adds one SMB account
(``observer``) to its own password database; ``smbd --foreground`` then runs as a child process
stopped by its PID (and its per-client children by theirs). Nothing of the system's Samba set-up is
read or changed. The account maps to the user running the tests (root on CI), so the test can
read the files the clients wrote.

``wrap`` turns the smbd command into one that runs elsewhere, e.g. inside a simulated host's
network namespace (:meth:`nightcrew.testing.hosts.Host.command`).
"""

from __future__ import annotations

import contextlib
import getpass
import os
import signal
import subprocess
from collections.abc import Callable, Sequence
from pathlib import Path

from nightcrew.testing.processes import descendants, free_port, wait_until_listening

__all__ = ["SMBD", "SambaServer", "samba_missing"]

SMBD = "/usr/sbin/smbd"
_PDBEDIT = "/usr/bin/pdbedit"
_STOP_TIMEOUT = 10.0

Wrap = Callable[[Sequence[str]], list[str]]


def samba_missing() -> list[str]:
    """What this machine lacks to run the test server (empty when nothing)."""
    return [f"{tool} (apt-get install samba)" for tool in (SMBD, _PDBEDIT) if not Path(tool).is_file()]


class SambaServer:
    """smbd on ``host:port`` sharing ``files/`` as ``[files]`` to ``username``/``password``.

    Args:
        directory: Where config, state, log and the shared files go (created if missing).
        host: Address to listen on (a loopback one, or a simulated host's address).
        port: TCP port; a free loopback port by default.
        wrap: Turns the command into one running elsewhere (a network namespace); as is by default.
    """

    share = "files"
    username = "observer"
    password = "secret-for-tests"

    def __init__(
        self, directory: Path, *, host: str = "127.0.0.1", port: int | None = None, wrap: Wrap | None = None
    ) -> None:
        self.directory = directory
        self.host = host
        self.port = port or free_port(host)
        self._wrap = wrap or list
        self._process: subprocess.Popen[bytes] | None = None

    @property
    def config(self) -> Path:
        return self.directory / "smb.conf"

    @property
    def files(self) -> Path:
        """The shared directory, as seen on this machine."""
        return self.directory / "files"

    @property
    def pid(self) -> int | None:
        """smbd's PID while it runs."""
        process = self._process
        return process.pid if process is not None and process.poll() is None else None

    def prepare(self) -> None:
        """Write smb.conf and add the account (once)."""
        d = self.directory.resolve()
        for sub in ("files", "private", "state", "cache", "lock", "pid", "ncalrpc", "binddns"):
            (d / sub).mkdir(parents=True, exist_ok=True)
        (d / "users.map").write_text(f"{getpass.getuser()} = {self.username}\n")
        self.config.write_text(
            "\n".join(
                [
                    "[global]",
                    "server role = standalone server",
                    f"interfaces = {self.host}",
                    "bind interfaces only = yes",
                    f"smb ports = {self.port}",
                    "disable netbios = yes",
                    "server min protocol = SMB2_10",
                    f"passdb backend = tdbsam:{d / 'private' / 'passdb.tdb'}",
                    f"username map = {d / 'users.map'}",
                    f"private dir = {d / 'private'}",
                    f"state directory = {d / 'state'}",
                    f"cache directory = {d / 'cache'}",
                    f"lock directory = {d / 'lock'}",
                    f"pid directory = {d / 'pid'}",
                    f"ncalrpc dir = {d / 'ncalrpc'}",
                    f"binddns dir = {d / 'binddns'}",
                    f"log file = {d / 'smbd.log'}",
                    "log level = 1",
                    "load printers = no",
                    "printing = bsd",
                    "printcap name = /dev/null",
                    "disable spoolss = yes",
                    "",
                    f"[{self.share}]",
                    f"path = {d / 'files'}",
                    "read only = no",
                    "",
                ]
            )
        )
        # The SMB account is a Unix user's: the one running the tests, known to SMB as username.
        result = subprocess.run(
            [_PDBEDIT, "-s", str(self.config), "-a", "-t", "-u", getpass.getuser()],
            input=f"{self.password}\n{self.password}\n",
            capture_output=True,
            text=True,
            timeout=60,
            check=False,
        )
        if result.returncode != 0:
            raise RuntimeError(f"pdbedit could not add the test account: {result.stderr.strip()}")

    def start(self) -> None:
        """Start smbd (writing config and account on first use); return once it accepts connections."""
        if self.pid is not None:
            return
        if not self.config.exists():
            self.prepare()
        log = self.directory / "smbd.out"
        with open(log, "ab") as output:
            self._process = subprocess.Popen(
                self._wrap(
                    [SMBD, "--foreground", "--no-process-group", "--debug-stdout", "-s", str(self.config)]
                ),
                stdin=subprocess.DEVNULL,
                stdout=output,
                stderr=output,
                # smbd signals its whole process group when it ends: give it one of its own.
                start_new_session=True,
            )
        wait_until_listening(self._process, self.port, what="smbd", log=log)

    def stop(self) -> None:
        """Stop smbd and its per-client processes by PID, so clients lose their links at once."""
        process, self._process = self._process, None
        if process is None or process.poll() is not None:
            return
        for child in descendants(process.pid):
            with contextlib.suppress(ProcessLookupError):
                os.kill(child, signal.SIGKILL)
        process.send_signal(signal.SIGTERM)
        try:
            process.wait(timeout=_STOP_TIMEOUT)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=_STOP_TIMEOUT)
