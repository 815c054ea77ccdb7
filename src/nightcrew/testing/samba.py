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

import getpass
import subprocess
from pathlib import Path

from nightcrew.testing.processes import ChildServer

__all__ = ["SMBD", "SambaServer", "samba_missing"]

SMBD = "/usr/sbin/smbd"
_PDBEDIT = "/usr/bin/pdbedit"


def samba_missing() -> list[str]:
    """What this machine lacks to run the test server (empty when nothing)."""
    return [f"{tool} (apt-get install samba)" for tool in (SMBD, _PDBEDIT) if not Path(tool).is_file()]


class SambaServer(ChildServer):
    """smbd on ``host:port`` sharing ``files/`` as ``[files]`` to ``username``/``password``.

    Config, state, log and the shared files go in ``directory`` (created if missing); the arguments
    are :class:`~nightcrew.testing.processes.ChildServer`'s.
    """

    share = "files"
    username = "observer"
    password = "secret-for-tests"

    @property
    def config(self) -> Path:
        return self.directory / "smb.conf"

    @property
    def files(self) -> Path:
        """The shared directory, as seen on this machine."""
        return self.directory / "files"

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
        # smbd signals its whole process group when it ends: give it one of its own.
        self._spawn(
            [SMBD, "--foreground", "--no-process-group", "--debug-stdout", "-s", str(self.config)],
            what="smbd",
            log=self.directory / "smbd.out",
            new_session=True,
        )
