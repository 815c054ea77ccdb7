"""One supervised module: a ``nightcrew run FILE`` child process, restarted when it exits.

States: ``running`` (the process lives), ``frozen`` (it lives but its event loop stopped beating
for ``frozen_after`` seconds, see nightcrew.supervisor._heartbeat: it is killed and restarted after
the backoff delay, and stays ``frozen`` until then), ``backoff`` (it exited; restarting after a
delay), ``stopping``, ``stopped`` (by request), ``failed`` (too many restarts: given up), ``broken``
(its configuration is wrong: exit code 2, or unreadable before the start; restarting cannot help
until the file is fixed and the module is started again). Every exit is logged with its reason: the
exit code or signal and the child's last error line.
"""

from __future__ import annotations

import asyncio
import collections
import ctypes
import logging
import os
import signal
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO

from nightcrew.supervisor._discovery import ModuleFile
from nightcrew.supervisor._heartbeat import (
    DEFAULT_FROZEN_AFTER,
    FD_VARIABLE,
    INTERVAL_VARIABLE,
    beat_interval,
    watch_heartbeat,
)
from nightcrew.supervisor._policy import RestartPolicy

__all__ = ["DEFAULT_STOP_TIMEOUT", "ModuleProcess", "ModuleStatus"]

#: Seconds a module may take to close after SIGTERM before it is killed. Closing parks the mount
#: and closes the roof, which take minutes on real hardware: killing a module halfway would leave
#: them to chance. A module whose event loop froze is killed sooner, by its missing heartbeat.
DEFAULT_STOP_TIMEOUT = 180.0

log = logging.getLogger(__name__)

_CONFIG_ERROR_EXIT = 2  # what `nightcrew` exits with on a ConfigError
_ERROR_PREFIX = "nightcrew: error: "
_PR_SET_PDEATHSIG = 1


@dataclass(frozen=True)
class ModuleStatus:
    """What ``nightcrew status`` shows of one module."""

    name: str
    state: str
    pid: int | None
    restarts: int
    since: float  # wall time of the last state change
    last_exit: str
    error: str
    config: str


class ModuleProcess:
    """Runs, watches and restarts one module process; nothing starts before :meth:`start`."""

    def __init__(
        self,
        module: ModuleFile,
        *,
        log_dir: Path,
        log_format: str,
        policy: RestartPolicy,
        stop_timeout: float = DEFAULT_STOP_TIMEOUT,
        frozen_after: float | None = DEFAULT_FROZEN_AFTER,
    ) -> None:
        self.module = module
        self.log_file = log_dir / f"{module.name}.log"
        self._log_format = log_format
        self._policy = policy
        self._stop_timeout = stop_timeout
        self._frozen_after = frozen_after
        self._frozen = ""  # why the running process counts as frozen, until it exits
        self._state = "stopped"
        self._since = time.time()
        self._restarts = 0
        self._last_exit = ""
        self._error = module.error or ""
        self._process: asyncio.subprocess.Process | None = None
        self._task: asyncio.Task[None] | None = None
        self._wanted = False
        self._stderr_tail: collections.deque[str] = collections.deque(maxlen=20)

    @property
    def name(self) -> str:
        return self.module.name

    def status(self) -> ModuleStatus:
        pid = self._process.pid if self._process is not None and self._process.returncode is None else None
        return ModuleStatus(
            self.name, self._state, pid, self._restarts, self._since, self._last_exit, self._error,
            str(self.module.path),
        )  # fmt: skip

    def start(self) -> None:
        """Start (again) if not running; forgets earlier failures."""
        if self._task is not None and not self._task.done():
            return
        self._wanted = True
        self._policy.reset()
        self._task = asyncio.get_running_loop().create_task(
            self._keep_running(), name=f"supervise {self.name}"
        )

    async def stop(self) -> None:
        """SIGTERM (the module closes cleanly), SIGKILL after ``stop_timeout``; no restart."""
        self._wanted = False
        if self._task is not None:
            process = self._process
            if process is not None and process.returncode is None:
                self._set_state("stopping")
                await self._terminate(process)
            self._task.cancel()
            await asyncio.gather(self._task, return_exceptions=True)
            self._task = None
        if self._state not in ("broken", "failed"):
            self._set_state("stopped")

    def _set_state(self, state: str, error: str | None = None) -> None:
        self._state, self._since = state, time.time()
        if error is not None:
            self._error = error

    async def _keep_running(self) -> None:
        if self.module.error:
            self._set_state("broken", self.module.error)
            log.error("%s not started: %s", self.name, self.module.error)
            return
        while self._wanted:
            started = time.monotonic()
            try:
                code = await self._run_once()
            except OSError as exc:  # cannot even start a process (no memory, no file descriptors ...)
                self._set_state("failed", f"cannot start its process: {exc}")
                log.error("%s: cannot start its process: %s", self.name, exc)
                return
            if self._stopping():
                return
            reason = _describe_exit(code)
            error = self._last_error()
            self._last_exit = f"{reason}: {error}" if error else reason
            if self._frozen:
                self._last_exit = f"frozen ({self._frozen}); {reason}"
            if code == _CONFIG_ERROR_EXIT:
                self._set_state("broken", error or reason)
                log.error(
                    "%s %s; not restarting until its configuration is fixed", self.name, self._last_exit
                )
                return
            delay = self._policy.after_exit(started, time.monotonic())
            if delay is None:
                self._set_state("failed", f"gave up after too many restarts; last: {self._last_exit}")
                log.error("%s %s; too many restarts, giving up", self.name, self._last_exit)
                return
            self._set_state("frozen" if self._frozen else "backoff", self._last_exit)
            log.warning("%s %s; restarting in %g s", self.name, self._last_exit, delay)
            await asyncio.sleep(delay)
            self._restarts += 1

    async def _run_once(self) -> int:
        self._stderr_tail.clear()
        self._frozen = ""
        read_fd, write_fd = os.pipe() if self._frozen_after is not None else (-1, -1)
        beats = os.fdopen(read_fd, "rb", buffering=0) if read_fd >= 0 else None
        try:
            try:
                process = await asyncio.create_subprocess_exec(
                    *self._command(),
                    stdin=asyncio.subprocess.DEVNULL,
                    stdout=asyncio.subprocess.DEVNULL,
                    stderr=asyncio.subprocess.PIPE,
                    start_new_session=True,  # Ctrl-C reaches the supervisor, which stops modules in order
                    preexec_fn=_die_with_parent,
                    pass_fds=(write_fd,) if write_fd >= 0 else (),
                    env=self._environment(write_fd),
                )
            finally:
                if write_fd >= 0:
                    os.close(write_fd)  # the child's copy is the only writer: its exit ends the watch
            return await self._watch(process, beats)
        finally:
            if beats is not None:
                beats.close()

    async def _watch(self, process: asyncio.subprocess.Process, beats: BinaryIO | None) -> int:
        """Collect the stderr tail (and watch the heartbeat) until the process exits; its exit code."""
        self._process = process
        self._set_state("running", "")
        log.info("%s started (pid %d)", self.name, process.pid)
        watch = None
        if beats is not None and self._frozen_after is not None:
            watch = asyncio.get_running_loop().create_task(
                watch_heartbeat(beats, self._frozen_after, lambda silent: self._kill_frozen(process, silent))
            )
        try:
            assert process.stderr is not None
            async for line in process.stderr:
                self._stderr_tail.append(line.decode(errors="replace").rstrip())
            return await process.wait()
        finally:
            if watch is not None:
                watch.cancel()
                await asyncio.gather(watch, return_exceptions=True)

    def _environment(self, write_fd: int) -> dict[str, str] | None:
        """The child's environment: ours, plus where and how often to beat (None: ours as it is)."""
        if self._frozen_after is None:
            return None
        interval = beat_interval(self._frozen_after)
        return {**os.environ, FD_VARIABLE: str(write_fd), INTERVAL_VARIABLE: repr(interval)}

    def _kill_frozen(self, process: asyncio.subprocess.Process, silent: float) -> None:
        """Its event loop stopped beating: report it ``frozen`` and kill it (restarted on its exit)."""
        if process.returncode is not None or self._stopping():
            return
        self._frozen = f"no heartbeat for {silent:g} s"
        self._set_state("frozen", self._frozen)
        log.error("%s (pid %d) is frozen: no heartbeat for %g s; killing it", self.name, process.pid, silent)
        process.kill()

    def _stopping(self) -> bool:
        """Whether :meth:`stop` was called (while the process ran: its exit is no crash)."""
        return not self._wanted

    def _command(self) -> list[str]:
        return [
            sys.executable, "-m", "nightcrew",
            "--log-file", str(self.log_file), "--log-format", self._log_format,
            "run", str(self.module.path),
        ]  # fmt: skip

    def _last_error(self) -> str:
        """The child's closing ``nightcrew: error:`` line, else its last logged error, else ""."""
        for line in reversed(self._stderr_tail):
            if line.startswith(_ERROR_PREFIX):
                return line.removeprefix(_ERROR_PREFIX)
        for line in reversed(self._stderr_tail):
            words = line.split(maxsplit=3)  # date time LEVEL logger: message (the text format)
            if len(words) == 4 and words[2] in ("ERROR", "CRITICAL"):
                return words[3]
        return ""

    async def _terminate(self, process: asyncio.subprocess.Process) -> None:
        process.send_signal(signal.SIGTERM)
        process.send_signal(signal.SIGCONT)  # a stopped process handles SIGTERM only once continued
        try:
            await asyncio.wait_for(process.wait(), self._stop_timeout)
        except TimeoutError:
            log.error("%s did not stop within %g s of SIGTERM; killing it", self.name, self._stop_timeout)
            process.kill()
            await process.wait()


def _describe_exit(code: int) -> str:
    if code < 0:
        return f"killed by {signal.Signals(-code).name}"
    return f"exited {code}"


def _die_with_parent() -> None:
    """In the child: get SIGTERM when the supervisor dies, so no module outlives it unsupervised."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
