"""Simulated hosts for tests: network namespaces joined by veth links, links that can be cut.

:class:`Hosts` makes one network namespace per host name and a point-to-point veth link (a /30 of
private addresses) between every pair of hosts, so cutting one link ("office" to "dome") leaves the
others up. With ``outside=[...]`` a host also gets a link to the test's own namespace, so the
test's asyncio code reaches servers on it (e.g. the XMPP server on "dome") like any client would.
The file system is shared: every host sees the same files, which keeps checking results simple.

How each host is made, and why it cleans up by itself:

* A **holder** process (``unshare --net``) owns the namespace, which lives as long as it does. It
  reads a pipe from the test process and exits at end of file; ``setpriv --pdeathsig KILL`` kills
  it if the test process dies. (``ip netns add`` would leave named namespaces behind after a
  crash; Python 3.11 has no ``os.setns``.)
* :meth:`Host.run` starts a program inside with ``nsenter --net=…`` (which does not fork, so the
  PID held is the program's own) under ``setpriv --pdeathsig KILL``.
* :meth:`Hosts.stop` stops the programs it started by PID (SIGTERM, then SIGKILL), then every
  other process still in one of its namespaces (daemons such as ``prosody -D``), found by PID in
  ``/proc``, then ends the holders: the kernel deletes the namespaces and their veth links.

:meth:`Hosts.cut` cuts a link silently, like a cable pulled between two switches: each end's
neighbour entry for the other is pinned to an unused MAC address, so frames go out and are dropped
by the peer; nobody is told, connections see only silence. :meth:`Hosts.restore` undoes it.
(No netem or firewall needed: both are often missing from containers.)

Needs root (CAP_NET_ADMIN, CAP_SYS_ADMIN), ``ip`` (iproute2), ``unshare``, ``nsenter``,
``setpriv`` (util-linux). Start hosts from the main thread: the parent-death signal follows the
thread that started a process.
"""

from __future__ import annotations

import contextlib
import ipaddress
import itertools
import os
import random
import shutil
import signal
import subprocess
import time
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import TracebackType

__all__ = ["OUTSIDE", "Host", "Hosts", "Link", "hosts_missing"]

#: Name of the test's own namespace as a peer (``host.address(OUTSIDE)``).
OUTSIDE = "outside"
_TOOLS = ("ip", "unshare", "nsenter", "setpriv")
_TIMEOUT = 10.0  # wall seconds for a namespace to appear or a process to stop
_POLL = 0.02
_NOWHERE = "02:00:00:00:00:01"  # a locally administered MAC address no interface has
_numbers = itertools.count()


def hosts_missing() -> list[str]:
    """What this machine lacks to simulate hosts (empty when nothing)."""
    missing = [tool for tool in _TOOLS if shutil.which(tool) is None]
    if os.geteuid() != 0:
        missing.append("root (network namespaces)")
    return missing


def _ip(*args: str, netns: str | None = None) -> None:
    command = ["ip", *args] if netns is None else ["nsenter", f"--net={netns}", "--", "ip", *args]
    result = subprocess.run(command, capture_output=True, text=True, timeout=30, check=False)
    if result.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed: {result.stderr.strip() or result.returncode}")


@dataclass
class Link:
    """A veth link between two hosts (or a host and :data:`OUTSIDE`): interface and address at
    each end."""

    ends: tuple[str, str]
    interfaces: tuple[str, str]
    addresses: tuple[str, str]
    cut: bool = False


class Host:
    """One simulated host: a network namespace and the programs started in it."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.addresses: dict[str, str] = {}  # peer → this host's address on the link to it
        self._holder: subprocess.Popen[bytes] | None = None
        self._processes: list[subprocess.Popen[bytes]] = []

    def __repr__(self) -> str:
        return f"Host({self.name!r}, {self.addresses})"

    @property
    def holder_pid(self) -> int:
        """PID of the process that holds the namespace."""
        if self._holder is None:
            raise RuntimeError(f"host {self.name} is not started")
        return self._holder.pid

    @property
    def started(self) -> bool:
        return self._holder is not None

    @property
    def netns(self) -> str:
        """Path of the namespace (``/proc/<holder>/ns/net``)."""
        return f"/proc/{self.holder_pid}/ns/net"

    def address(self, seen_from: str) -> str:
        """This host's address as ``seen_from`` (a host name or :data:`OUTSIDE`) reaches it."""
        try:
            return self.addresses[seen_from]
        except KeyError:
            raise LookupError(f"no link between {self.name} and {seen_from}") from None

    def command(self, args: Sequence[str]) -> list[str]:
        """``args`` as a command that runs in this host and dies with the test process."""
        return ["nsenter", f"--net={self.netns}", "--", "setpriv", "--pdeathsig", "KILL", *args]

    def run(
        self,
        args: Sequence[str],
        *,
        log: Path | None = None,
        env: Mapping[str, str] | None = None,
        cwd: Path | None = None,
    ) -> subprocess.Popen[bytes]:
        """Start ``args`` in this host (output to ``log``, else discarded); stopped by :meth:`stop`."""
        output = open(log, "ab") if log is not None else subprocess.DEVNULL  # noqa: SIM115
        try:
            process = subprocess.Popen(
                self.command(args),
                stdin=subprocess.DEVNULL,
                stdout=output,
                stderr=output,
                env=dict(env) if env is not None else None,
                cwd=cwd,
            )
        finally:
            if not isinstance(output, int):
                output.close()
        self._processes.append(process)
        return process

    def start(self) -> None:
        own = _netns_of(os.getpid())
        self._holder = subprocess.Popen(
            ["setpriv", "--pdeathsig", "KILL", "unshare", "--net", "--", "sh", "-c", "exec cat >/dev/null"],
            stdin=subprocess.PIPE,
        )
        deadline = time.monotonic() + _TIMEOUT
        while _netns_of(self._holder.pid) in (own, None):
            if self._holder.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"unshare --net made no namespace for {self.name} ({self._holder.poll()})")
            time.sleep(_POLL)
        _ip("link", "set", "lo", "up", netns=self.netns)

    def stop(self) -> None:
        """Stop its programs, then whatever else runs in its namespace, by PID; end the namespace."""
        for process in self._processes:
            if process.poll() is None:
                process.send_signal(signal.SIGTERM)
        for process in self._processes:
            _wait_or_kill(process)
        self._processes.clear()
        holder, self._holder = self._holder, None
        if holder is None:
            return
        namespace = _netns_of(holder.pid)
        for pid in _pids_in(namespace, besides=holder.pid):
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
        if holder.stdin is not None:
            holder.stdin.close()
        _wait_or_kill(holder)


class Hosts:
    """Simulated hosts, a link between every two of them, and links to the test's namespace.

    Args:
        names: Host names, e.g. ``["dome", "camera", "office"]``.
        outside: Hosts that also get a link to the test's own namespace.

    Use as a context manager (or :meth:`start` and :meth:`stop`)::

        with Hosts(["dome", "office"], outside=["dome"]) as hosts:
            server = hosts["dome"].run(["my-server", "--listen", "0.0.0.0:8000"])
            client = hosts["office"].run(["my-client", hosts["dome"].address("office") + ":8000"])
            hosts.cut("office", "dome")
    """

    def __init__(self, names: Iterable[str], *, outside: Iterable[str] = ()) -> None:
        self.hosts = {name: Host(name) for name in names}
        if len(self.hosts) < 1 or OUTSIDE in self.hosts:
            raise ValueError(f"name at least one host, none called {OUTSIDE!r}")
        self._outside = list(outside)
        for name in self._outside:
            if name not in self.hosts:
                raise ValueError(f"unknown host {name!r} in outside")
        self.links: dict[frozenset[str], Link] = {}

    def __getitem__(self, name: str) -> Host:
        return self.hosts[name]

    def start(self) -> None:
        """Make the namespaces and the links between them."""
        try:
            for host in self.hosts.values():
                host.start()
            names = list(self.hosts)
            pairs = [(a, b) for i, a in enumerate(names) for b in names[i + 1 :]]
            pairs += [(name, OUTSIDE) for name in self._outside]
            subnets = _free_subnets(len(pairs))
            for (a, b), subnet in zip(pairs, subnets, strict=True):
                self._link(a, b, subnet)
        except BaseException:
            self.stop()
            raise

    def _link(self, a: str, b: str, subnet: ipaddress.IPv4Network) -> None:
        number = f"{os.getpid() % 0xFFFF:x}{next(_numbers):x}"
        interfaces = (f"nc{number}a", f"nc{number}b")
        addresses = tuple(str(address) for address in subnet.hosts())
        _ip("link", "add", "name", interfaces[0], "type", "veth", "peer", "name", interfaces[1])
        for end, interface, address in zip((a, b), interfaces, addresses, strict=True):
            netns = None if end == OUTSIDE else self.hosts[end].netns
            if netns is not None:
                _ip("link", "set", interface, "netns", netns.split("/")[2])
            _ip("addr", "add", f"{address}/30", "dev", interface, netns=netns)
            _ip("link", "set", interface, "up", netns=netns)
        self.hosts[a].addresses[b] = addresses[0]
        if b != OUTSIDE:
            self.hosts[b].addresses[a] = addresses[1]
        self.links[frozenset((a, b))] = Link(
            (a, b), (interfaces[0], interfaces[1]), (addresses[0], addresses[1])
        )

    def link(self, a: str, b: str) -> Link:
        try:
            return self.links[frozenset((a, b))]
        except KeyError:
            raise LookupError(f"no link between {a} and {b}") from None

    def cut(self, a: str, b: str) -> None:
        """Cut the link silently: frames between ``a`` and ``b`` are lost from now on."""
        self._pin(self.link(a, b), cut=True)

    def restore(self, a: str, b: str) -> None:
        """Mend a cut link."""
        self._pin(self.link(a, b), cut=False)

    def _pin(self, link: Link, *, cut: bool) -> None:
        for index, end in enumerate(link.ends):
            netns = None if end == OUTSIDE else self.hosts[end].netns
            interface, peer = link.interfaces[index], link.addresses[1 - index]
            if cut:
                _ip(
                    "neigh",
                    "replace",
                    peer,
                    "lladdr",
                    _NOWHERE,
                    "dev",
                    interface,
                    "nud",
                    "permanent",
                    netns=netns,
                )
            else:
                _ip("neigh", "del", peer, "dev", interface, netns=netns)  # learnt again by ARP
        link.cut = cut

    def stop(self) -> None:
        """Stop every program and end every namespace (their links go with them); safe twice."""
        for host in self.hosts.values():
            host.stop()
        for link in self.links.values():
            if OUTSIDE in link.ends:  # its outside end goes with the namespace's end; wait for that
                deadline = time.monotonic() + _TIMEOUT
                outside_end = link.interfaces[link.ends.index(OUTSIDE)]
                while Path(f"/sys/class/net/{outside_end}").exists() and time.monotonic() < deadline:
                    time.sleep(_POLL)
        self.links.clear()

    def __enter__(self) -> Hosts:
        self.start()
        return self

    def __exit__(
        self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.stop()


def _netns_of(pid: int) -> str | None:
    try:
        return os.readlink(f"/proc/{pid}/ns/net")
    except OSError:
        return None


def _pids_in(namespace: str | None, *, besides: int) -> list[int]:
    """PIDs of the processes in network namespace ``namespace`` (as ``readlink`` names it)."""
    if namespace is None:
        return []
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and int(entry.name) != besides and _netns_of(int(entry.name)) == namespace:
            found.append(int(entry.name))
    return found


def _wait_or_kill(process: subprocess.Popen[bytes]) -> None:
    try:
        process.wait(timeout=_TIMEOUT)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(timeout=_TIMEOUT)


def _routed_networks() -> list[ipaddress.IPv4Network]:
    out = subprocess.run(
        ["ip", "-4", "route", "show", "table", "all"], capture_output=True, text=True, check=True, timeout=30
    )
    networks = []
    for line in out.stdout.splitlines():
        words = line.split()
        word = words[1] if len(words) > 1 and words[0] in ("broadcast", "local") else (words or [""])[0]
        with contextlib.suppress(ValueError):  # "default", "unreachable" ...
            networks.append(ipaddress.IPv4Network(word, strict=False))
    return networks


def _free_subnets(count: int) -> list[ipaddress.IPv4Network]:
    """``count`` /30 subnets of a random 10.x.y.0/24 that nothing on this machine routes."""
    routed = [net for net in _routed_networks() if net.prefixlen > 0]
    rng = random.Random()
    for _ in range(100):
        block = ipaddress.IPv4Network(f"10.{rng.randrange(64, 255)}.{rng.randrange(256)}.0/24")
        if not any(block.overlaps(net) for net in routed):
            return list(block.subnets(new_prefix=30))[:count]
    raise RuntimeError("no free 10.x.y.0/24 for the simulated hosts")
