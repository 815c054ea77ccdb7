"""The simulated observatory on three simulated hosts, each host's modules under ``nightcrew up``.

* **dome**: Prosody (``nightcrew server start``), roof, telescope, the weather station
  ``conditions`` (``examples/sim-processes``)
  and a safety watchdog watching the station and the office's mastermind; OpenSSH and Samba
  serving the frames' copies.
* **camera**: the camera and the HTTP file cache it writes into (``examples/multi-host``), and
  the filter wheel (a FITS header provider).
* **office**: two image writers (``examples/multi-host/writer-ssh.yaml``, ``writer-smb.yaml``)
  reading frames from the camera's cache and writing them to the dome, and a stand-in mastermind
  (a plain module: the watchdog's heartbeat from the office).

Each host runs one supervisor (``nightcrew up DIR``) over a directory of small module files that
include the examples; every module is its own process, restarted by its supervisor when killed.
The test process reaches Prosody over a link of its own to "dome" and drives the night from there.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import yaml

from nightcrew.server import (
    Account,
    accounts_from_configs,
    create_missing_passwords,
    init_server,
    policy_for_accounts,
    stop_server,
)
from nightcrew.supervisor import send_request
from nightcrew.testing.hosts import OUTSIDE, Hosts
from nightcrew.testing.samba import SambaServer
from nightcrew.testing.sshd import SshServer

REPOSITORY = Path(__file__).resolve().parents[2]
EXAMPLES = REPOSITORY / "examples"
DOMAIN = "observatory.test"
PASSWORD = "secret-for-tests"
ROOM = "nightcrew"
SECRETS = "secrets"
XMPP_PORT, SSH_PORT, SMB_PORT, CACHE_PORT = 5222, 22, 445, 37081
CLOCK_START = "2026-11-10T17:50:00"
CLOCK_SPEED = 20.0
#: Clock seconds the watchdog lets the weather or the mastermind be silent (20 wall seconds).
SILENCE_LIMIT = 400
#: Wall seconds between the office's XMPP pings and a ping's time to answer (defaults 10 and 10):
#: the office notices the cut link within 6 s, so a short cut outlasts every limit many times over.
OFFICE_PINGS = "  ping_interval: 2\n  ping_timeout: 4\n"
_COMM = (
    f"comm:\n  <<: !include {EXAMPLES}/sim-processes/xmpp.yaml\n  jid: {{name}}@{DOMAIN}\n"
    "  password: !include ${{SIM_XMPP_SECRETS}}/{name}.password\n"  # as the examples name theirs
)
_CLOCK = f"clock: !include {EXAMPLES}/sim-processes/clock.yaml\n"
_OVERLAY = _COMM + _CLOCK
#: Host → module name → the module file's text (most include an example unchanged).
MODULE_FILES: dict[str, dict[str, str]] = {
    "dome": {
        **{
            name: f"<<: !include {EXAMPLES}/sim-processes/{name}.yaml\n"
            for name in ("roof", "telescope", "conditions")
        },
        "watchdog": (
            "class: nightcrew.modules.safety.SafetyWatchdog\n"
            f"watch: {{conditions: {SILENCE_LIMIT}, mastermind: {SILENCE_LIMIT}}}\n"
            "roof: roof\ntelescope: telescope\nweather: conditions\ninterval: 20\nanswer_timeout: 40\n"
            + _OVERLAY.format(name="watchdog")
        ),
    },
    "camera": {
        "camera": f"<<: !include {EXAMPLES}/multi-host/camera.yaml\n",
        "cache": f"<<: !include {EXAMPLES}/multi-host/cache.yaml\n",
        "filters": f"<<: !include {EXAMPLES}/sim-processes/filters.yaml\n",
    },
    "office": {
        **{
            name: f"<<: !include {EXAMPLES}/multi-host/{name}.yaml\n" + _COMM.format(name=name) + OFFICE_PINGS
            for name in ("writer-ssh", "writer-smb")
        },
        "mastermind": (
            "class: nightcrew.modules.Module\n" + _COMM.format(name="mastermind") + OFFICE_PINGS + _CLOCK
        ),
    },
}
MODULES = [name for modules in MODULE_FILES.values() for name in modules]
HOST_OF = {name: host for host, modules in MODULE_FILES.items() for name in modules}


@dataclass
class Observatory:
    """What the set-up made: hosts, servers, supervisors and where the copies land."""

    hosts: Hosts
    directory: Path
    ssh: SshServer
    samba: SambaServer
    supervisors: dict[str, subprocess.Popen[bytes]] = field(default_factory=dict)
    #: Control sockets by host (short paths: a Unix socket path must stay below 108 bytes).
    sockets: dict[str, Path] = field(default_factory=dict)

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
        """A module's log (or a host's supervisor log, by host name)."""
        path = self.directory / "logs" / f"{name}.log"
        if name in self.supervisors:
            path = self.directory / f"supervisor-{name}.log"
        return path.read_text(errors="replace") if path.exists() else ""

    def check_alive(self) -> None:
        for host, process in self.supervisors.items():
            assert process.poll() is None, (
                f"supervisor on {host} exited {process.returncode}:\n{self.log(host)}"
            )

    async def status(self, host: str) -> dict[str, dict[str, Any]]:
        """The supervisor's status of every module on ``host``, by module name."""
        reply = await send_request(self.sockets[host], {"command": "status", "module": None})
        return {module["name"]: module for module in reply["modules"]}

    async def control(self, command: str, name: str) -> None:
        """Ask module ``name``'s supervisor to ``stop`` it (by request: no restart) or ``start`` it."""
        await send_request(self.sockets[HOST_OF[name]], {"command": command, "module": name})


def start(directory: Path) -> Observatory:
    """Build everything; on failure, stop what was started."""
    hosts = Hosts(["dome", "camera", "office"], outside=["dome"])
    dome = hosts["dome"]
    hosts.start()
    observatory = Observatory(
        hosts,
        directory,
        SshServer(directory / "sshd", host=dome.address("office"), port=SSH_PORT, wrap=dome.command),
        SambaServer(directory / "samba", host=dome.address("office"), port=SMB_PORT, wrap=dome.command),
    )
    try:
        environments = _environments(observatory)
        paths = []
        for host, modules in MODULE_FILES.items():
            files = directory / f"{host}-modules"
            (files / SECRETS).mkdir(parents=True)
            for name, text in modules.items():
                (files / f"{name}.yaml").write_text(text)
                paths.append(files / f"{name}.yaml")
        # docs/operations.md, step 2 on the dome: one random password per module account, made and
        # read as `nightcrew server init xmpp examples/sim-processes/*.yaml examples/multi-host/*.yaml`
        # (and the test's own files) does; each host gets only its own modules' password files, in
        # the folder its SIM_XMPP_SECRETS names. The operator (this test) is a person of its own.
        on_dome = {"SIM_XMPP_SECRETS": str(directory / SECRETS)}
        examples = sorted([*EXAMPLES.glob("sim-processes/*.yaml"), *EXAMPLES.glob("multi-host/*.yaml")])
        create_missing_passwords([*examples, *paths], environ={**environments["dome"], **on_dome})
        accounts = [Account("operator", DOMAIN, PASSWORD, person=True)]
        for host, modules in MODULE_FILES.items():
            own = [directory / f"{host}-modules" / f"{name}.yaml" for name in modules]
            accounts += accounts_from_configs(own, environ={**environments[host], **on_dome})
            for name in modules:
                password = f"{name}.password"
                shutil.copy2(directory / SECRETS / password, directory / f"{host}-modules" / SECRETS)
        init_server(observatory.xmpp_directory, accounts, host="0.0.0.0", port=XMPP_PORT, domains=[DOMAIN])
        # The starting policy, as `nightcrew server init` writes it for these accounts.
        (directory / "access.policy").write_text(yaml.safe_dump(policy_for_accounts(accounts)))
        server = dome.run(
            [sys.executable, "-m", "nightcrew", "server", "start", str(observatory.xmpp_directory)],
            log=directory / "prosody-start.log",
        )
        assert server.wait(timeout=60) == 0, (directory / "prosody-start.log").read_text()
        observatory.ssh.start()
        observatory.samba.start()
        sockets = Path(tempfile.mkdtemp(prefix="nc-hosts-"))
        for host in MODULE_FILES:
            files = directory / f"{host}-modules"
            socket = observatory.sockets[host] = sockets / f"{host}.sock"
            observatory.supervisors[host] = hosts[host].run(
                [sys.executable, "-m", "nightcrew", "up", str(files), "--socket", str(socket),
                 "--log-dir", str(directory / "logs")],
                log=directory / f"supervisor-{host}.log", env=environments[host], cwd=directory,
            )  # fmt: skip
    except BaseException:
        stop(observatory)
        raise
    return observatory


def _environments(observatory: Observatory) -> dict[str, dict[str, str]]:
    dome, camera = observatory.hosts["dome"], observatory.hosts["camera"]
    directory, ssh, samba = observatory.directory, observatory.ssh, observatory.samba
    common = {
        "PATH": "/usr/sbin:/usr/bin:/sbin:/bin",
        "HOME": str(directory),
        "SIM_XMPP_DOMAIN": DOMAIN,
        "SIM_XMPP_ROOM": ROOM,
        "SIM_XMPP_CA_FILE": observatory.ca_file,
        "SIM_XMPP_POLICY": str(directory / "access.policy"),
        "SIM_CLOCK_START": CLOCK_START,
        "SIM_CLOCK_SPEED": str(CLOCK_SPEED),
        "SIM_WALL_START": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%S"),
        "NC_FILECACHE_PORT": str(CACHE_PORT),
        "NC_FILECACHE_TOKEN": "cache-secret-for-tests",
        "NC_FILECACHE_DIR": str(directory / "filecache"),
        "NC_FILECACHE_URL": f"http://{camera.address('office')}:{CACHE_PORT}",
    }
    office = {
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
        "NC_SMB_SHARE": samba.share,
        "NC_SMB_USER": samba.username,
        "NC_SMB_PASSWORD": samba.password,
        "NC_SMB_ROOT": "frames",
        "NC_WRITER_STATE_DIR": str(directory),
    }
    environments = {
        "dome": {**common, "SIM_XMPP_SERVER": f"127.0.0.1:{XMPP_PORT}"},
        "camera": {**common, "SIM_XMPP_SERVER": f"{dome.address('camera')}:{XMPP_PORT}"},
        "office": office,
    }
    for host, environment in environments.items():  # each host its own modules' passwords
        environment["SIM_XMPP_SECRETS"] = str(directory / f"{host}-modules" / SECRETS)
    return environments


def stop(observatory: Observatory) -> list[str]:
    """Stop everything; returns the supervisors that did not exit 0 on SIGTERM, with their logs."""
    problems = []
    for process in observatory.supervisors.values():
        if process.poll() is None:
            process.terminate()  # each stops its modules cleanly (roof closes, telescope parks)
    for host, process in observatory.supervisors.items():
        try:
            code = process.wait(timeout=120)
        except subprocess.TimeoutExpired:
            problems.append(f"the supervisor on {host} did not stop within 120 s of SIGTERM")
            continue
        if code != 0:
            problems.append(f"the supervisor on {host} exited {code}:\n{observatory.log(host)[-3000:]}")
    stop_server(observatory.xmpp_directory)
    observatory.ssh.stop()
    observatory.samba.stop()
    observatory.hosts.stop()
    return problems
