"""``nightcrew run``: modules from YAML in one process, clean stop on signals."""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import os
import queue
import signal
import subprocess
import sys
import threading
import time
from datetime import datetime
from pathlib import Path

import pytest

from nightcrew.cli.main import main
from nightcrew.cli.run import build_modules, run_modules
from nightcrew.errors import InvalidArgumentError
from nightcrew.events import TestEvent
from nightcrew.modules.test import StandAlone

from ..comm.sample import Calculator, Listener
from .modules import Asker

REPO = Path(__file__).resolve().parents[2]


def _write(path: Path, text: str) -> str:
    path.write_text(text)
    return str(path)


async def test_two_modules_from_yaml_call_each_other_and_exchange_events(tmp_path: Path) -> None:
    files = [
        _write(tmp_path / "calc.yaml", "class: tests.comm.sample.Calculator\n"),
        _write(tmp_path / "listener.yaml", "class: tests.comm.sample.Listener\n"),
        _write(tmp_path / "asker.yaml", "class: tests.cli.modules.Asker\ncalculator: calc\n"),
    ]
    calc, listener, asker = build_modules(files)
    assert isinstance(calc, Calculator) and isinstance(listener, Listener) and isinstance(asker, Asker)
    assert (calc.name, asker.name) == ("calc", "asker")  # named after their files
    stop = asyncio.Event()
    runner = asyncio.create_task(run_modules([calc, listener, asker], stop))
    await asyncio.wait_for(asker.done.wait(), 5)
    await asyncio.wait_for(listener.arrived.wait(), 5)
    stop.set()
    await runner
    assert asker.answers[0] == 42.0
    error = asker.answers[1]
    assert isinstance(error, InvalidArgumentError) and error.module == "calc"
    assert listener.received == [(TestEvent(message="asked"), "asker")]
    assert {m.state.value for m in (calc, listener, asker)} == {"closed"}


def test_bad_config_is_one_line_with_exit_code_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = _write(tmp_path / "bad.yaml", "class: nightcrew.modules.test.StandAlone\ninterval: ten\n")
    assert main(["run", bad]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith(f"nightcrew: error: {bad}:2: key 'interval':")
    assert "expected" in err[0] and "ten" in err[0]


#: Lines "Hello world" awaited before the signal, and the wall seconds allowed for them.
HELLOS, HELLO_DEADLINE_S = 4, 120.0


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_standalone_logs_at_its_interval_and_stops_cleanly(tmp_path: Path, sig: signal.Signals) -> None:
    config = _write(
        tmp_path / "hello.yaml",
        "class: nightcrew.modules.test.StandAlone\nmessage: Hello world\ninterval: 0.2\n",
    )
    proc = subprocess.Popen(
        [sys.executable, "-m", "nightcrew", "run", config],
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO)},
    )
    # The signal goes once the module has logged a few times (not after a wall-clock guess).
    lines: queue.Queue[str] = queue.Queue()
    seen: list[str] = []
    with proc:

        def read_lines() -> None:
            for line in proc.stderr or ():
                lines.put(line)

        reader = threading.Thread(target=read_lines, daemon=True)
        reader.start()
        deadline = time.monotonic() + HELLO_DEADLINE_S
        while sum(line.rstrip().endswith("Hello world") for line in seen) < HELLOS:
            left = deadline - time.monotonic()
            if left <= 0 or proc.poll() is not None:
                proc.kill()
                pytest.fail(f"fewer than {HELLOS} lines 'Hello world' within {HELLO_DEADLINE_S:g} s: {seen}")
            with contextlib.suppress(queue.Empty):
                seen.append(lines.get(timeout=min(left, 1.0)))
        proc.send_signal(sig)
        assert proc.wait(timeout=30) == 0, "".join(seen)
        reader.join(timeout=30)
    while not lines.empty():
        seen.append(lines.get_nowait())
    err = "".join(seen)
    stamps = [line.split(" INFO")[0] for line in err.splitlines() if line.endswith("Hello world")]
    assert len(stamps) >= HELLOS, err
    times = [datetime.strptime(stamp, "%Y-%m-%d %H:%M:%S,%f") for stamp in stamps]
    gaps = [(b - a).total_seconds() for a, b in itertools.pairwise(times)]
    assert min(gaps) >= 0.19, gaps  # its interval (0.2 s) apart, however busy the machine
    assert "hello is ready" in err and "stopping" in err
    assert "Traceback" not in err


def test_version() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "nightcrew", "--version"], capture_output=True, text=True, check=True
    )
    assert out.stdout.startswith("nightcrew ")


def test_module_context_reaches_children_from_yaml(tmp_path: Path) -> None:
    config = _write(
        tmp_path / "hello.yaml",
        """class: nightcrew.modules.test.StandAlone
clock: {class: nightcrew.clock.AcceleratedClock, start: "2026-11-22T18:00:00", speed: 60}
vfs:
  class: nightcrew.vfs.VirtualFileSystem
  roots:
    cache: {class: nightcrew.vfs.MemoryFile}
site: {latitude: 51.56, longitude: 9.94, elevation: 201}
""",
    )
    (module,) = build_modules([config])
    child = module.add_child(StandAlone(name="child"))
    assert child.clock is module.clock and module.clock.speed == 60
    assert child.vfs is module.vfs and list(module.vfs.roots) == ["cache"]
    assert child.site == module.site and module.site is not None and module.site.latitude == 51.56
