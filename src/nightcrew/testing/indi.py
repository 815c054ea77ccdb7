"""indiserver with the indi-bin simulators in a private network namespace, for tests and benchmarks.

``indiserver`` has no bind-address option: it listens on every interface of its network namespace.
So it never runs in the host's namespace. The choice made here:

* A **holder** process (``unshare --net``) owns a fresh network namespace; the namespace lives as
  long as the holder does. The holder reads its stdin (a pipe from the test process) and exits at
  end of file, and ``setpriv --pdeathsig KILL`` kills it if the test process dies: either way the
  namespace and everything in it disappears by itself.
* A **veth pair** links the namespace to the host: the host end gets ``10.a.b.1/30``, the
  namespace end ``10.a.b.2/30`` (a random /30 not routed on this machine). Only the test's
  own host end can reach the namespace, and deleting the namespace deletes the pair.
* ``indiserver`` runs inside (``nsenter --net=/proc/HOLDER/ns/net``, which does not fork, so the
  PID we hold is indiserver's own) with ``--pdeathsig KILL``. Its drivers exit when indiserver's
  pipe to them closes.

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

import ipaddress
import itertools
import os
import random
import shutil
import signal
import socket
import subprocess
import time
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import IO

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

_TOOLS = ("ip", "unshare", "nsenter", "setpriv", "indiserver")
_READY_TIMEOUT = 30.0  # wall seconds; indiserver and its drivers start within ~1 s on an idle machine
_POLL = 0.02
_interface_numbers = itertools.count()


def indi_missing() -> list[str]:
    """What this machine lacks to run indiserver in a namespace (empty when nothing)."""
    missing = [tool for tool in _TOOLS if shutil.which(tool) is None]
    missing += [driver for driver in SIMULATORS if shutil.which(driver) is None]
    if os.geteuid() != 0:
        missing.append("root (network namespaces)")
    return missing


def indi_available() -> bool:
    """Whether indiserver and the simulators can run here."""
    return not indi_missing()


def _run(*args: str) -> None:
    result = subprocess.run(args, capture_output=True, text=True, timeout=30, check=False)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} failed: {result.stderr.strip() or result.returncode}")


def _routed_networks() -> list[ipaddress.IPv4Network]:
    out = subprocess.run(
        ["ip", "-4", "route", "show", "table", "all"], capture_output=True, text=True, check=True
    )
    networks = []
    for line in out.stdout.splitlines():
        word = line.split()[0] if line.split() else ""
        if word in ("broadcast", "local") and len(line.split()) > 1:
            word = line.split()[1]
        try:
            networks.append(ipaddress.IPv4Network(word, strict=False))
        except ValueError:
            continue  # "default", "unreachable" ...
    return networks


def _free_subnet() -> ipaddress.IPv4Network:
    routed = _routed_networks()
    rng = random.Random()
    for _ in range(100):
        candidate = ipaddress.IPv4Network(
            (f"10.{rng.randrange(64, 255)}.{rng.randrange(256)}.{rng.randrange(64) * 4}", 30)
        )
        if not any(candidate.overlaps(net) for net in routed if net.prefixlen > 0):
            return candidate
    raise RuntimeError("no free 10.x.y.z/30 subnet found for the test namespace")


class PrivateNetwork:
    """A network namespace of its own, reachable from the host through a veth pair.

    ``host`` is the namespace's address as seen from the test process.
    """

    def __init__(self) -> None:
        self._holder: subprocess.Popen[bytes] | None = None
        self.host = ""
        self.host_side = ""

    @property
    def pid(self) -> int:
        if self._holder is None:
            raise RuntimeError("the private network is not started")
        return self._holder.pid

    @property
    def netns_path(self) -> str:
        return f"/proc/{self.pid}/ns/net"

    def start(self) -> None:
        own = os.readlink("/proc/self/ns/net")
        self._holder = subprocess.Popen(
            ["setpriv", "--pdeathsig", "KILL", "unshare", "--net", "--", "sh", "-c", "exec cat >/dev/null"],
            stdin=subprocess.PIPE,
        )
        deadline = time.monotonic() + _READY_TIMEOUT
        while _netns_of(self.pid) in (own, None):
            if self._holder.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"unshare --net did not make a namespace (exit {self._holder.poll()})")
            time.sleep(_POLL)
        subnet = _free_subnet()
        host_address, inner_address = list(subnet.hosts())
        number = f"{os.getpid():x}{next(_interface_numbers):x}"
        self.host_side, inner_side = f"nc{number}h", f"nc{number}n"
        try:
            _run(
                "ip",
                "link",
                "add",
                self.host_side,
                "type",
                "veth",
                "peer",
                "name",
                inner_side,
                "netns",
                str(self.pid),
            )
            _run("ip", "addr", "add", f"{host_address}/30", "dev", self.host_side)
            _run("ip", "link", "set", self.host_side, "up")
            inside = ("nsenter", f"--net={self.netns_path}", "--")
            _run(*inside, "ip", "link", "set", "lo", "up")
            _run(*inside, "ip", "addr", "add", f"{inner_address}/30", "dev", inner_side)
            _run(*inside, "ip", "link", "set", inner_side, "up")
        except BaseException:
            self.stop()
            raise
        self.host = str(inner_address)

    def command(self, args: Sequence[str]) -> list[str]:
        """``args`` as a command that runs inside the namespace and dies with the test process."""
        return ["nsenter", f"--net={self.netns_path}", "--", "setpriv", "--pdeathsig", "KILL", *args]

    def stop(self) -> None:
        """End the holder: the namespace and the veth pair go with it."""
        holder, self._holder = self._holder, None
        if holder is None:
            return
        if holder.stdin is not None:
            holder.stdin.close()
        try:
            holder.wait(timeout=10)
        except subprocess.TimeoutExpired:
            holder.kill()
            holder.wait(timeout=10)
        # The kernel deletes the namespace, and with it the veth pair, shortly after its last process.
        deadline = time.monotonic() + 10.0
        while self.host_side and Path(f"/sys/class/net/{self.host_side}").exists():
            if time.monotonic() > deadline:
                _run("ip", "link", "del", self.host_side)
                break
            time.sleep(_POLL)


def _netns_of(pid: int) -> str | None:
    try:
        return os.readlink(f"/proc/{pid}/ns/net")
    except OSError:
        return None


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
        if self.network._holder is None:
            self.network.start()
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
        for child in _children(pid):
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


def _children(pid: int) -> list[int]:
    children = []
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            children += [int(c) for c in (task / "children").read_text().split()]
        except OSError:
            continue
    return children


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
