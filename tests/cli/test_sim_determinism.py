"""``nightcrew sim --seed 3`` twice, once with both cores busy: the same night, byte for byte.

The night runs on the virtual clock, so neither the machine's speed nor its load may change what
happens: the event record (events.jsonl), every frame (headers and pixels) and the report must be
identical. The second run has two ``yes > /dev/null`` loads beside it (started here and stopped
by their PIDs), so that thread jobs finish in other orders and the event loop runs late.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

#: Clock hours from 18:00 UTC: the focus series, science frames and the rain of ``interruption``.
HOURS = "1"


def run_night(out: Path) -> None:
    command = [sys.executable, "-m", "nightcrew", "sim", "--out", str(out), "--seed", "3"]
    command += ["--start", "18:00", "--hours", HOURS, "--weather", "interruption"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=600, check=False)
    assert result.returncode == 0, result.stderr[-2000:]


@contextmanager
def both_cores_busy() -> Iterator[None]:
    loads = [subprocess.Popen(["yes"], stdout=subprocess.DEVNULL) for _ in range(os.cpu_count() or 2)]
    try:
        yield
    finally:
        for load in loads:
            load.kill()  # by PID: only what this test started
            load.wait()


def frame_checksums(out: Path) -> dict[str, str]:
    return {
        p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted((out / "frames").glob("*.fits"))
    }


@pytest.mark.timeout(1200)
def test_the_same_seed_gives_the_same_night_on_a_quiet_and_on_a_busy_machine(tmp_path: Path) -> None:
    quiet, busy = tmp_path / "quiet" / "night", tmp_path / "busy" / "night"
    run_night(quiet)
    with both_cores_busy():
        run_night(busy)

    events = (quiet / "events.jsonl").read_bytes()
    assert events.count(b"\n") > 50, "the night recorded its events"
    assert b'"kind": "NewImageEvent"' in events
    assert events == (busy / "events.jsonl").read_bytes()
    frames = frame_checksums(quiet)
    assert len(frames) >= 5, "focus and science frames were written"
    assert frames == frame_checksums(busy)
    assert (quiet / "report.html").read_bytes() == (busy / "report.html").read_bytes()
