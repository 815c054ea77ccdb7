"""A private OpenSSH server for tests: its own config, host key, user key and port.

:class:`SshServer` writes everything into one directory — ``sshd_config``, a host key, a user key
pair with its ``authorized_keys``, and a ``known_hosts`` file that names the host key for the
address and port the server listens on — and runs Debian's ``/usr/sbin/sshd -D`` in the
foreground, so the PID we hold is the server's own and it is stopped by that PID. The system's
sshd service is never touched. The login is the user running the tests (root on CI), with the
key only: no password, no PAM.

``wrap`` turns the sshd command into one that runs elsewhere, e.g. inside a simulated host's
network namespace (:meth:`nightcrew.testing.hosts.Host.command`).
"""

from __future__ import annotations

import getpass
import shutil
import subprocess
from pathlib import Path

from nightcrew.testing.processes import ChildServer, Wrap

__all__ = ["SSHD", "SshServer", "sshd_missing"]

SSHD = "/usr/sbin/sshd"
_TOOLS = ("ssh-keygen",)


def sshd_missing() -> list[str]:
    """What this machine lacks to run the test server (empty when nothing)."""
    missing = [] if Path(SSHD).is_file() else ["sshd (apt-get install openssh-server)"]
    return missing + [tool for tool in _TOOLS if shutil.which(tool) is None]


class SshServer(ChildServer):
    """sshd on ``host:port`` with files in ``directory``.

    Config, keys, log and served files go in ``directory`` (created if missing); the arguments are
    :class:`~nightcrew.testing.processes.ChildServer`'s.
    """

    def __init__(
        self, directory: Path, *, host: str = "127.0.0.1", port: int | None = None, wrap: Wrap | None = None
    ) -> None:
        super().__init__(directory, host=host, port=port, wrap=wrap)
        self.username = getpass.getuser()

    @property
    def client_key(self) -> Path:
        """The private key the client logs in with."""
        return self.directory / "user_key"

    @property
    def known_hosts(self) -> Path:
        """A known_hosts file naming this server's host key at its address and port."""
        return self.directory / "known_hosts"

    @property
    def files(self) -> Path:
        """A directory clients may use for their files."""
        return self.directory / "files"

    def prepare(self) -> None:
        """Write config and keys (once; a restart keeps the host key, as a real server does)."""
        self.directory.mkdir(parents=True, exist_ok=True)
        self.files.mkdir(exist_ok=True)
        host_key, user_key = self.directory / "host_key", self.client_key
        for key in (host_key, user_key):
            if not key.exists():
                _run("ssh-keygen", "-q", "-t", "ed25519", "-N", "", "-C", "nightcrew-test", "-f", str(key))
        (self.directory / "authorized_keys").write_text(Path(f"{user_key}.pub").read_text())
        public = Path(f"{host_key}.pub").read_text().split()
        name = self.host if self.port == 22 else f"[{self.host}]:{self.port}"  # known_hosts syntax
        self.known_hosts.write_text(f"{name} {public[0]} {public[1]}\n")
        d = self.directory.resolve()
        (self.directory / "sshd_config").write_text(
            "\n".join(
                [
                    f"ListenAddress {self.host}:{self.port}",
                    f"HostKey {d / 'host_key'}",
                    f"AuthorizedKeysFile {d / 'authorized_keys'}",
                    f"PidFile {d / 'sshd.pid'}",
                    "PermitRootLogin prohibit-password",
                    "PubkeyAuthentication yes",
                    "PasswordAuthentication no",
                    "KbdInteractiveAuthentication no",
                    "UsePAM no",
                    "StrictModes no",  # the test directory lies under a world-writable /tmp
                    "Subsystem sftp internal-sftp",
                    "LogLevel ERROR",
                    "",
                ]
            )
        )

    def start(self) -> None:
        """Start sshd (writing config and keys on first use); return once it accepts connections."""
        if self.pid is not None:
            return
        self.prepare()
        Path("/run/sshd").mkdir(mode=0o755, exist_ok=True)  # sshd's privilege-separation directory
        self._spawn(
            [SSHD, "-D", "-e", "-f", str(self.directory / "sshd_config")],
            what="sshd",
            log=self.directory / "sshd.log",
        )


def _run(*args: str) -> None:
    result = subprocess.run(args, capture_output=True, text=True, timeout=60, check=False)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} failed: {result.stderr.strip() or result.returncode}")
