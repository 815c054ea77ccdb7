"""Helpers for test fixtures that run servers as child processes: ports, readiness, descendants,
and :class:`ChildServer`, the start-wait-stop life of one such server."""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import time
from collections.abc import Callable, Sequence
from pathlib import Path

__all__ = [
    "ChildServer",
    "Wrap",
    "descendants",
    "end_process",
    "free_port",
    "listening_ports",
    "wait_until_listening",
]

_READY_TIMEOUT = 30.0  # wall seconds; the servers start within ~1 s on an idle machine
_STOP_TIMEOUT = 10.0
_POLL = 0.02
_LISTEN = "0A"  # TCP state LISTEN in /proc/net/tcp


def free_port(host: str = "127.0.0.1") -> int:
    """A TCP port free on ``host`` now (an address of this network namespace)."""
    with socket.socket(socket.AF_INET6 if ":" in host else socket.AF_INET) as sock:
        sock.bind((host, 0))
        port: int = sock.getsockname()[1]
        return port


def listening_ports(pid: int) -> set[int]:
    """TCP ports listened on in the network namespace of process ``pid`` (any address)."""
    ports = set()
    for table in ("tcp", "tcp6"):
        try:
            lines = Path(f"/proc/{pid}/net/{table}").read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            if len(fields) > 3 and fields[3] == _LISTEN:
                ports.add(int(fields[1].rsplit(":", 1)[1], 16))
    return ports


def wait_until_listening(
    process: subprocess.Popen[bytes], port: int, *, what: str, log: Path | None = None
) -> None:
    """Return once something listens on ``port`` in ``process``'s network namespace.

    Read from ``/proc/<pid>/net``, so it works for a server inside another network namespace
    without a route to it. Raises RuntimeError, with the end of ``log``, if the process exits or
    nothing listens within 30 wall seconds.
    """
    deadline = time.monotonic() + _READY_TIMEOUT
    while port not in listening_ports(process.pid):
        if process.poll() is not None or time.monotonic() > deadline:
            if process.poll() is None:
                process.kill()
                process.wait()
            tail = log.read_text(errors="replace").strip().splitlines()[-5:] if log and log.exists() else []
            raise RuntimeError(
                f"{what} did not listen on port {port} (exit {process.returncode}): " + " | ".join(tail)
            )
        time.sleep(_POLL)


def end_process(
    process: subprocess.Popen[bytes], signal_number: int = signal.SIGTERM, *, timeout: float = _STOP_TIMEOUT
) -> None:
    """Send ``signal_number`` and wait for the exit; SIGKILL it if it is not gone within ``timeout``."""
    process.send_signal(signal_number)
    try:
        process.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(timeout=timeout)


def descendants(pid: int) -> list[int]:
    """PIDs of every process below ``pid`` (children first, then theirs)."""
    found: list[int] = []
    queue = [pid]
    while queue:
        parent = queue.pop(0)
        for task in Path(f"/proc/{parent}/task").glob("*"):
            try:
                children = [int(child) for child in (task / "children").read_text().split()]
            except OSError:
                continue
            found += children
            queue += children
    return found


#: Turns a command into one that runs elsewhere, e.g. :meth:`nightcrew.testing.hosts.Host.command`.
Wrap = Callable[[Sequence[str]], list[str]]


class ChildServer:
    """A server run as a child process on ``host:port`` with its files in ``directory``.

    Subclasses write their configuration and call :meth:`_spawn`; :meth:`stop` ends the server and
    its per-client children by PID (SIGTERM ends only the listener, and the sessions would live on in
    its children), so clients lose their links at once.

    Args:
        directory: Where config, log and served files go.
        host: Address to listen on (a loopback one, or a simulated host's address).
        port: TCP port; a free one on ``host`` by default.
        wrap: Turns the command into one running elsewhere (a network namespace); as is by default.
    """

    def __init__(
        self, directory: Path, *, host: str = "127.0.0.1", port: int | None = None, wrap: Wrap | None = None
    ) -> None:
        self.directory = directory
        self.host = host
        self.port = port or free_port(host)
        self._wrap = wrap or list
        self._process: subprocess.Popen[bytes] | None = None

    @property
    def pid(self) -> int | None:
        """The server's PID while it runs."""
        process = self._process
        return process.pid if process is not None and process.poll() is None else None

    def _spawn(self, command: Sequence[str], *, what: str, log: Path, new_session: bool = False) -> None:
        """Run ``command`` (wrapped) with its output appended to ``log``; return once it listens."""
        with open(log, "ab") as output:
            self._process = subprocess.Popen(
                self._wrap(command),
                stdin=subprocess.DEVNULL,
                stdout=output,
                stderr=output,
                start_new_session=new_session,
            )
        wait_until_listening(self._process, self.port, what=what, log=log)

    def stop(self) -> None:
        """Stop the server and its children by PID; safe to call twice."""
        process, self._process = self._process, None
        if process is None or process.poll() is not None:
            return
        for child in descendants(process.pid):
            with contextlib.suppress(ProcessLookupError):
                os.kill(child, signal.SIGKILL)
        end_process(process)
