"""The simulated hosts themselves: links between them, a cut that is silent, and cleanup."""

from __future__ import annotations

import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from nightcrew.testing.hosts import OUTSIDE, Hosts, hosts_missing
from nightcrew.testing.processes import listening_ports
from tests.vfs.remote_servers import require

PORT = 7000
#: Connects to argv[1]:PORT; prints "ok", "timeout" (silence) or the error (a refusal, no route).
CLIENT = f"""
import socket, sys
try:
    socket.create_connection((sys.argv[1], {PORT}), timeout=2).close()
    print("ok")
except TimeoutError:
    print("timeout")
except OSError as exc:
    print(exc)
"""
SERVER = f"import socket, time; s = socket.create_server(('0.0.0.0', {PORT})); time.sleep(600)"


@pytest.fixture
def hosts() -> Iterator[Hosts]:
    require(hosts_missing())
    with Hosts(["dome", "camera", "office"], outside=["dome"]) as simulated:
        yield simulated


def reach(hosts: Hosts, source: str, target: str) -> str:
    """What a TCP connection from ``source`` to ``target``'s PORT meets."""
    command = hosts[source].command([sys.executable, "-c", CLIENT, hosts[target].address(source)])
    return subprocess.run(command, capture_output=True, text=True, timeout=30, check=True).stdout.strip()


def wait_listening(process: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + 30
    while PORT not in listening_ports(process.pid):
        assert process.poll() is None and time.monotonic() < deadline, "the server did not listen"
        time.sleep(0.02)


def test_links_cut_and_restore(hosts: Hosts) -> None:
    server = hosts["dome"].run([sys.executable, "-c", SERVER])
    wait_listening(server)
    assert reach(hosts, "office", "dome") == "ok"
    assert reach(hosts, "camera", "dome") == "ok"
    with socket.create_connection((hosts["dome"].address(OUTSIDE), PORT), timeout=5):
        pass  # the test's own namespace reaches dome over its link
    assert hosts["dome"].address("office") != hosts["dome"].address("camera")

    hosts.cut("office", "dome")
    assert reach(hosts, "office", "dome") == "timeout"  # silence, not a refusal
    assert reach(hosts, "camera", "dome") == "ok"  # the other links stay up
    hosts.restore("office", "dome")
    assert reach(hosts, "office", "dome") == "ok"


def test_stop_leaves_nothing_behind(tmp_path: Path) -> None:
    require(hosts_missing())
    hosts = Hosts(["a", "b"], outside=["a"])
    hosts.start()
    netns = {name: os.readlink(hosts[name].netns) for name in ("a", "b")}
    started = hosts["a"].run([sys.executable, "-c", SERVER])
    # A daemon: forks away from the process we started, as prosody -D does.
    hosts["b"].run(["sh", "-c", f"sleep 600 & echo $! > {tmp_path / 'daemon.pid'}"]).wait(timeout=10)
    daemon = int((tmp_path / "daemon.pid").read_text())
    outside_interface = hosts.link("a", OUTSIDE).interfaces[1]
    assert Path(f"/sys/class/net/{outside_interface}").exists()
    hosts.stop()
    assert started.poll() is not None
    assert not Path(f"/proc/{daemon}").exists() or "Z" in Path(f"/proc/{daemon}/stat").read_text().split()[2]
    assert not Path(f"/sys/class/net/{outside_interface}").exists()
    for pid_dir in Path("/proc").iterdir():
        if pid_dir.name.isdigit():
            try:
                assert os.readlink(pid_dir / "ns" / "net") not in netns.values(), f"{pid_dir} still inside"
            except OSError:
                continue
    hosts.stop()  # safe twice
