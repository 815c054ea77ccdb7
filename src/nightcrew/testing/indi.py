"""indiserver with the indi-bin simulators in a private network namespace, for tests and benchmarks.

``indiserver`` has no bind-address option: it listens on every interface of its network namespace.
So it never runs in the host's namespace. The choice made here:

* The namespace is a :class:`~nightcrew.testing.hosts.Hosts` of one host with a veth link to the
  test's own namespace (see there how its holder process makes it clean up by itself).
* ``indiserver`` runs inside (``nsenter --net=...``, which does not fork, so the PID we hold is
  indiserver's own) with ``--pdeathsig KILL``. Its drivers exit when indiserver's pipe to them
  closes.

So ordinary async tests in the test process reach the server at ``server.host:server.port``, like
any remote indiserver a user points nightcrew at, and :meth:`IndiServer.kill` /
:meth:`IndiServer.start` kill and restart it by PID for the restart tests. (Alternatives rejected:
running the nightcrew side in the namespace as a subprocess hides it from the test's own asyncio
code; ``unshare --net`` for the whole pytest worker would cut every other test off the host's
loopback services; Python 3.11 has no ``os.setns``.)

Needs root (CAP_NET_ADMIN and CAP_SYS_ADMIN), ``ip``, ``unshare``, ``nsenter``, ``setpriv``
(util-linux, iproute2) and Debian's indi-bin. Start servers from the main thread: the parent-death
signal follows the thread that started the process.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import IO

from nightcrew.testing.hosts import OUTSIDE, Hosts, hosts_missing
from nightcrew.testing.processes import descendants

__all__ = [
    "SIMULATORS",
    "IndiServer",
    "PrivateNetwork",
    "indi_available",
    "indi_missing",
]

#: Simulator driver → the INDI device name it defines.
SIMULATORS: dict[str, str] = {
    "indi_simulator_telescope": "Telescope Simulator",
    "indi_simulator_ccd": "CCD Simulator",
    "indi_simulator_focus": "Focuser Simulator",
    "indi_simulator_wheel": "Filter Simulator",
    "indi_simulator_dome": "Dome Simulator",
    "indi_simulator_weather": "Weather Simulator",
    "indi_simulator_rotator": "Rotator Simulator",
}

_READY_TIMEOUT = 30.0  # wall seconds; indiserver and its drivers start within ~1 s on an idle machine
_POLL = 0.02
_HOST = "indi"


def indi_missing() -> list[str]:
    """What this machine lacks to run indiserver in a namespace (empty when nothing)."""
    missing = [program for program in ("indiserver", *SIMULATORS) if shutil.which(program) is None]
    return hosts_missing() + missing


def indi_available() -> bool:
    """Whether indiserver and the simulators can run here."""
    return not indi_missing()


class PrivateNetwork:
    """A network namespace of its own, reachable from the host through a veth pair.

    ``host`` is the namespace's address as seen from the test process; ``host_side`` the veth
    interface on the test's side.
    """

    def __init__(self) -> None:
        self._hosts = Hosts([_HOST], outside=[_HOST])

    @property
    def started(self) -> bool:
        return self._hosts[_HOST].started

    @property
    def pid(self) -> int:
        """PID of the process that holds the namespace."""
        return self._hosts[_HOST].holder_pid

    @property
    def host(self) -> str:
        return self._hosts[_HOST].address(OUTSIDE)

    @property
    def test_address(self) -> str:
        """The test's own address on the link, as servers in the namespace see it."""
        link = self._hosts.link(_HOST, OUTSIDE)
        return link.addresses[link.ends.index(OUTSIDE)]

    @property
    def host_side(self) -> str:
        link = self._hosts.link(_HOST, OUTSIDE)
        return link.interfaces[link.ends.index(OUTSIDE)]

    def start(self) -> None:
        self._hosts.start()

    def command(self, args: Sequence[str]) -> list[str]:
        """``args`` as a command that runs inside the namespace and dies with the test process."""
        return self._hosts[_HOST].command(args)

    def stop(self) -> None:
        """End the namespace: the veth pair goes with it; safe to call twice."""
        self._hosts.stop()


class IndiServer:
    """indiserver with the given drivers inside a :class:`PrivateNetwork`.

    Args:
        drivers: Driver executables, e.g. ``["indi_simulator_telescope", "indi_simulator_ccd"]``.
        network: The namespace to run in; a new one (stopped with the server) when None.
        port: TCP port inside the namespace.
        log_dir: Where indiserver's output goes (``indiserver-<pid>.log``); discarded when None.
    """

    def __init__(
        self,
        drivers: Iterable[str],
        *,
        network: PrivateNetwork | None = None,
        port: int = 7624,
        log_dir: Path | None = None,
    ) -> None:
        self.drivers = list(drivers)
        if not self.drivers:
            raise ValueError("name at least one driver")
        self._own_network = network is None
        self.network = network or PrivateNetwork()
        self.port = port
        self._log_dir = log_dir
        self._process: subprocess.Popen[bytes] | None = None
        self._home: str | None = None

    @property
    def host(self) -> str:
        return self.network.host

    @property
    def pid(self) -> int | None:
        """indiserver's PID while it runs."""
        process = self._process
        return process.pid if process is not None and process.poll() is None else None

    @property
    def devices(self) -> list[str]:
        """INDI device names of the simulators among the drivers."""
        return [SIMULATORS[d] for d in self.drivers if d in SIMULATORS]

    def start(self) -> None:
        """Start indiserver (and the namespace on first use); return when every simulator's device
        has defined its properties."""
        if self._process is not None and self._process.poll() is None:
            return
        if not self.network.started:
            self.network.start()
        if self._home is None:
            # The drivers keep park data and configuration in $HOME/.indi: a home of this server's
            # own (kept across restarts) so that no test meets what another one (or a developer's
            # KStars) left there, nor a file half-written by a server running beside it.
            self._home = tempfile.mkdtemp(prefix="nightcrew-indi-home-")
        output: IO[bytes] | int = subprocess.DEVNULL
        if self._log_dir is not None:
            self._log_dir.mkdir(parents=True, exist_ok=True)
            output = open(self._log_dir / f"indiserver-{time.time_ns()}.log", "wb")  # noqa: SIM115
        try:
            self._process = subprocess.Popen(
                self.network.command(["indiserver", "-v", "-p", str(self.port), *self.drivers]),
                stdin=subprocess.DEVNULL,
                stdout=output,
                stderr=output,
                env={**os.environ, "HOME": self._home},
            )
        finally:
            if not isinstance(output, int):
                output.close()
        self._wait_until_defined(self.devices)

    def _wait_until_defined(self, devices: list[str]) -> None:
        deadline = time.monotonic() + _READY_TIMEOUT
        missing = set(devices)
        while True:
            if self._process is None or self._process.poll() is not None:
                raise RuntimeError(f"indiserver exited with {self._process and self._process.returncode}")
            try:
                missing = _undefined_devices(self.host, self.port, devices, deadline)
            except OSError:
                missing = set(devices)
            if not missing:
                return
            if time.monotonic() > deadline:
                raise RuntimeError(
                    f"indiserver's devices not defined within {_READY_TIMEOUT:g} s: {sorted(missing)}"
                )
            time.sleep(_POLL * 5)

    def kill(self) -> None:
        """Kill indiserver (SIGKILL, by PID) and wait for it; its drivers exit on their own."""
        process, self._process = self._process, None
        if process is None or process.poll() is not None:
            return
        os.kill(process.pid, signal.SIGKILL)
        process.wait(timeout=10)

    def driver_pids(self) -> dict[str, int]:
        """PIDs of indiserver's running driver processes by executable name."""
        pid = self.pid
        if pid is None:
            return {}
        found = {}
        for child in descendants(pid):
            try:
                program = Path(f"/proc/{child}/cmdline").read_bytes().split(b"\0")[0].decode()
            except OSError:
                continue
            if Path(program).name in self.drivers:
                found[Path(program).name] = child
        return found

    def stop(self) -> None:
        """Kill indiserver and, if this server made it, the namespace; safe to call twice."""
        self.kill()
        if self._own_network:
            self.network.stop()
        home, self._home = self._home, None
        if home is not None:
            shutil.rmtree(home, ignore_errors=True)


def _undefined_devices(host: str, port: int, devices: list[str], deadline: float) -> set[str]:
    """Devices not yet seen in a def*Vector of the server's answer to getProperties."""
    missing = set(devices)
    with socket.create_connection((host, port), timeout=2.0) as sock:
        sock.sendall(b'<getProperties version="1.7"/>\n')
        buffer = b""
        quiet_until = time.monotonic() + 1.0
        while missing and time.monotonic() < min(deadline, quiet_until):
            sock.settimeout(max(0.05, min(deadline, quiet_until) - time.monotonic()))
            try:
                chunk = sock.recv(65536)
            except TimeoutError:
                break
            if not chunk:
                break
            buffer = buffer[-200:] + chunk
            for device in list(missing):
                if f'device="{device}"'.encode() in buffer:
                    missing.discard(device)
            quiet_until = time.monotonic() + 1.0
    return missing
