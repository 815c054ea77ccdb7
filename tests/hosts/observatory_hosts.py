"""The simulated observatory on three simulated hosts, each module a ``nightcrew run`` process.

* **dome**: Prosody (``nightcrew server start``), one process with roof, telescope and weather
  (``examples/sim-processes``), OpenSSH and Samba serving the frames' copies.
* **camera**: one process with the camera and the HTTP file cache it writes into
  (``examples/multi-host/camera.yaml``, ``cache.yaml``).
* **office**: two image writers (``examples/multi-host/writer-ssh.yaml``, ``writer-smb.yaml``),
  each its own process, reading frames from the camera's cache and writing them to the dome.

The test process reaches Prosody over a link of its own to "dome" and drives the night from there.
"""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path

from nightcrew.server import Account, init_server, stop_server
from nightcrew.testing.hosts import OUTSIDE, Hosts
from nightcrew.testing.samba import SambaServer
from nightcrew.testing.sshd import SshServer

REPOSITORY = Path(__file__).resolve().parents[2]
EXAMPLES = REPOSITORY / "examples"
DOMAIN = "observatory.test"
PASSWORD = "secret-for-tests"
ROOM = "nightcrew"
XMPP_PORT, SSH_PORT, SMB_PORT, CACHE_PORT = 5222, 22, 445, 37081
CLOCK_START = "2026-11-10T17:50:00"
CLOCK_SPEED = 20.0
#: Module name → (host, configuration files of its process). One process per entry.
PROCESSES: dict[str, tuple[str, list[Path]]] = {
    "dome": (
        "dome",
        [EXAMPLES / "sim-processes" / f"{name}.yaml" for name in ("roof", "telescope", "weather")],
    ),
    "camera": (
        "camera",
        [EXAMPLES / "multi-host" / "camera.yaml", EXAMPLES / "multi-host" / "cache.yaml"],
    ),
    "writer-ssh": ("office", [EXAMPLES / "multi-host" / "writer-ssh.yaml"]),
    "writer-smb": ("office", [EXAMPLES / "multi-host" / "writer-smb.yaml"]),
}
MODULES = ["roof", "telescope", "weather", "camera", "cache", "writer-ssh", "writer-smb"]


@dataclass
class Observatory:
    """What the set-up made: hosts, servers, processes and where the copies land."""

    hosts: Hosts
    directory: Path
    ssh: SshServer
    samba: SambaServer
    processes: dict[str, subprocess.Popen[bytes]] = field(default_factory=dict)

    @property
    def xmpp_directory(self) -> Path:
        return self.directory / "xmpp"

    @property
    def ca_file(self) -> str:
        return str(self.xmpp_directory / "certs" / f"{DOMAIN}.crt")

    @property
    def xmpp_server(self) -> str:
        """Prosody as the test process reaches it."""
        return f"{self.hosts['dome'].address(OUTSIDE)}:{XMPP_PORT}"

    @property
    def ssh_copies(self) -> Path:
        return self.ssh.files / "frames"

    @property
    def smb_copies(self) -> Path:
        return self.samba.files / "frames"

    def log(self, name: str) -> str:
        path = self.directory / f"{name}.log"
        return path.read_text(errors="replace") if path.exists() else ""

    def check_alive(self) -> None:
        for name, process in self.processes.items():
            assert process.poll() is None, f"{name} exited {process.returncode}:\n{self.log(name)}"


def start(directory: Path) -> Observatory:
    """Build everything; on failure, stop what was started."""
    hosts = Hosts(["dome", "camera", "office"], outside=["dome"])
    dome, camera = hosts["dome"], hosts["camera"]
    hosts.start()
    observatory = Observatory(
        hosts,
        directory,
        SshServer(directory / "sshd", host=dome.address("office"), port=SSH_PORT, wrap=dome.command),
        SambaServer(directory / "samba", host=dome.address("office"), port=SMB_PORT, wrap=dome.command),
    )
    try:
        accounts = [Account(name, DOMAIN, PASSWORD) for name in [*MODULES, "operator"]]
        init_server(observatory.xmpp_directory, accounts, host="0.0.0.0", port=XMPP_PORT, domains=[DOMAIN])
        server = dome.run(
            [sys.executable, "-m", "nightcrew", "server", "start", str(observatory.xmpp_directory)],
            log=directory / "prosody-start.log",
        )
        assert server.wait(timeout=60) == 0, (directory / "prosody-start.log").read_text()
        observatory.ssh.start()
        observatory.samba.start()
        common = {
            "PATH": "/usr/sbin:/usr/bin:/sbin:/bin",
            "HOME": str(directory),
            "SIM_XMPP_PASSWORD": PASSWORD,
            "SIM_XMPP_DOMAIN": DOMAIN,
            "SIM_XMPP_ROOM": ROOM,
            "SIM_XMPP_CA_FILE": observatory.ca_file,
            "SIM_CLOCK_START": CLOCK_START,
            "SIM_CLOCK_SPEED": str(CLOCK_SPEED),
            "SIM_WALL_START": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%S"),
            "NC_FILECACHE_PORT": str(CACHE_PORT),
            "NC_FILECACHE_TOKEN": "cache-secret-for-tests",
            "NC_FILECACHE_URL": f"http://{camera.address('office')}:{CACHE_PORT}",
        }
        ssh = observatory.ssh
        office_env = {
            **common,
            "SIM_XMPP_SERVER": f"{dome.address('office')}:{XMPP_PORT}",
            "NC_SSH_HOST": dome.address("office"),
            "NC_SSH_PORT": str(SSH_PORT),
            "NC_SSH_USER": ssh.username,
            "NC_SSH_ROOT": str(observatory.ssh_copies),
            "NC_SSH_KEY": str(ssh.client_key),
            "NC_SSH_KNOWN_HOSTS": str(ssh.known_hosts),
            "NC_SSH_KEEPALIVE": "2",
            "NC_SMB_HOST": dome.address("office"),
            "NC_SMB_PORT": str(SMB_PORT),
            "NC_SMB_SHARE": observatory.samba.share,
            "NC_SMB_USER": observatory.samba.username,
            "NC_SMB_PASSWORD": observatory.samba.password,
            "NC_SMB_ROOT": "frames",
        }
        environments = {
            "dome": {**common, "SIM_XMPP_SERVER": f"127.0.0.1:{XMPP_PORT}"},
            "camera": {**common, "SIM_XMPP_SERVER": f"{dome.address('camera')}:{XMPP_PORT}"},
            "office": office_env,
        }
        for name, (host, configs) in PROCESSES.items():
            observatory.processes[name] = hosts[host].run(
                [sys.executable, "-m", "nightcrew", "run", *map(str, configs)],
                log=directory / f"{name}.log",
                env=environments[host],
                cwd=directory,
            )
    except BaseException:
        stop(observatory)
        raise
    return observatory


def stop(observatory: Observatory) -> list[str]:
    """Stop everything; returns the module processes that did not exit 0 on SIGTERM, with logs."""
    hosts = observatory.hosts
    problems = []
    for process in observatory.processes.values():
        if process.poll() is None:
            process.terminate()
    for name, process in observatory.processes.items():
        try:
            code = process.wait(timeout=20)
        except subprocess.TimeoutExpired:
            problems.append(f"{name} did not stop within 20 s of SIGTERM")
            continue
        if code != 0:
            problems.append(f"{name} exited {code}:\n{observatory.log(name)[-3000:]}")
    stop_server(observatory.xmpp_directory)
    observatory.ssh.stop()
    observatory.samba.stop()
    hosts.stop()
    return problems
