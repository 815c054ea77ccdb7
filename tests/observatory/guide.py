"""Running a guide's shell blocks as written: each ```sh block in order, in one working directory and
environment carried from block to block, as a user typing them into one terminal would.

A line ending in `` &`` is started in the background (and stopped by its PID at the end, SIGTERM,
as Ctrl-C would); before the next line runs, the runner waits until what it started answers
(alpaca-simulators: its HTTP port; ``nightcrew up``: every module past starting), since a user
also waits for that before typing on. Everything else runs with ``bash -e`` and must succeed.
"""

from __future__ import annotations

import os
import re
import shlex
import signal
import subprocess
import time
import urllib.error
import urllib.request
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["Guide", "shell_blocks"]

_BLOCK = re.compile(r"^```sh\n(.*?)^```", re.MULTILINE | re.DOTALL)
_START_TIMEOUT = 120.0  # wall seconds for a background server or the modules to come up (busy machine)


def shell_blocks(markdown: str) -> list[str]:
    """The ```sh blocks of a markdown text, in order."""
    return _BLOCK.findall(markdown)


@dataclass
class Guide:
    """Runs blocks in ``home`` (``$HOME``, so ``~`` is there) with ``environment``."""

    home: Path
    environment: dict[str, str]
    transcript: list[str] = field(default_factory=list)
    background: list[subprocess.Popen[bytes]] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.cwd = self.home
        self.environment = {**self.environment, "HOME": str(self.home)}
        self._state = self.home / ".guide-state"

    def run_block(self, block: str, timeout: float = 300.0) -> str:
        """Run one block; its output (stdout and stderr). AssertionError with the output on failure."""
        output = []
        chunk: list[str] = []
        for line in block.splitlines():
            command = line.split(" #", 1)[0].rstrip()
            if command.endswith(" &") and not chunk:
                self._start(command.removesuffix("&").strip())
            elif command.endswith(" &"):
                output.append(self._run("\n".join(chunk), timeout))
                chunk = []
                self._start(command.removesuffix("&").strip())
            else:
                chunk.append(line)
        if any(line.strip() for line in chunk):
            output.append(self._run("\n".join(chunk), timeout))
        return "".join(output)

    def _prelude(self) -> str:
        prelude = f"cd {shlex.quote(str(self.cwd))}\n"
        if self._state.exists():
            prelude += f"source {shlex.quote(str(self._state))}\n"
        return prelude

    def _run(self, commands: str, timeout: float) -> str:
        state = shlex.quote(str(self._state))
        save = f"\nexport -p > {state}.new && pwd > {state}.cwd\n"
        script = self._prelude() + commands + save
        done = subprocess.run(
            ["bash", "-e", "-o", "pipefail", "-c", script],
            env=self.environment,
            capture_output=True,
            timeout=timeout,
            check=False,
        )
        shown = done.stdout.decode(errors="replace") + done.stderr.decode(errors="replace")
        self.transcript.append(f"$ {commands}\n{shown}")
        assert done.returncode == 0, f"exit {done.returncode} from:\n{commands}\n{shown}"
        Path(f"{self._state}.new").replace(self._state)
        self.cwd = Path(Path(f"{self._state}.cwd").read_text().strip())
        return shown

    def _start(self, command: str) -> None:
        script = self._prelude() + f"exec {command}"
        process = subprocess.Popen(
            ["bash", "-c", script], env=self.environment, stdin=subprocess.DEVNULL, start_new_session=True
        )
        self.background.append(process)
        self.transcript.append(f"$ {command} &  (pid {process.pid})")
        if "alpaca-simulators" in command:
            port = re.search(r"--port (\d+)", command)
            assert port is not None
            self._wait_http(f"http://127.0.0.1:{port.group(1)}/api/v1/telescope/0/connected", process)
        elif "nightcrew up" in command:
            self._wait_modules_started(process)

    def _wait_http(self, url: str, process: subprocess.Popen[bytes]) -> None:
        deadline = time.monotonic() + _START_TIMEOUT
        while time.monotonic() < deadline:
            assert process.poll() is None, f"{process.args!r} exited with {process.returncode}"
            try:
                with urllib.request.urlopen(url, timeout=2.0):
                    return
            except (urllib.error.URLError, ConnectionError, TimeoutError):
                time.sleep(0.2)  # still starting; bounded by the deadline
        raise AssertionError(f"nothing answered {url} within {_START_TIMEOUT:g} s")

    def _wait_modules_started(self, process: subprocess.Popen[bytes]) -> None:
        """Until every module of ``nightcrew status`` is ready (its log says so) or given up on."""
        deadline = time.monotonic() + _START_TIMEOUT
        shown = ""
        while time.monotonic() < deadline:
            assert process.poll() is None, f"nightcrew up exited with {process.returncode}"
            done = subprocess.run(
                ["bash", "-c", self._prelude() + "nightcrew status"],
                env=self.environment,
                capture_output=True,
                timeout=60,
                check=False,
            )
            shown = done.stdout.decode()
            rows = [line.split() for line in shown.splitlines()[1:] if line.strip()]
            if rows and all(self._settled(row[0], row[1]) for row in rows):
                return
            time.sleep(0.5)  # bounded by the deadline
        raise AssertionError(f"modules still starting after {_START_TIMEOUT:g} s:\n{shown}")

    def _settled(self, module: str, state: str) -> bool:
        if state in ("broken", "failed"):
            return True
        log = self.cwd / "logs" / f"{module}.log"
        return state == "running" and log.exists() and f"{module} is ready" in log.read_text(errors="replace")

    def stop(self) -> None:
        """SIGTERM to everything started in the background (by PID), as Ctrl-C would; then wait."""
        for process in reversed(self.background):
            if process.poll() is None:
                os.kill(process.pid, signal.SIGTERM)
                try:
                    process.wait(timeout=90)
                except subprocess.TimeoutExpired:
                    os.kill(process.pid, signal.SIGKILL)
                    process.wait(timeout=10)
