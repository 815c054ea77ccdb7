"""Helpers for test fixtures that run servers as child processes: ports, readiness, descendants."""

from __future__ import annotations

import socket
import subprocess
import time
from pathlib import Path

__all__ = ["descendants", "free_port", "listening_ports", "wait_until_listening"]

_READY_TIMEOUT = 30.0  # wall seconds; the servers start within ~1 s on an idle machine
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
