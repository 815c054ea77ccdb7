"""The supervisor: every module of a directory in its own process, kept running, controlled by socket.

Started by ``nightcrew up DIR``. SIGTERM and SIGINT stop it cleanly: each module gets SIGTERM (its
own clean shutdown: ``nightcrew run`` closes it), in the reverse order of starting, then the
supervisor exits.
"""

from __future__ import annotations

import asyncio
import dataclasses
import logging
import signal
from collections.abc import Callable
from pathlib import Path
from typing import Any

from nightcrew.supervisor._control import ControlServer, SupervisorError
from nightcrew.supervisor._discovery import module_files
from nightcrew.supervisor._heartbeat import DEFAULT_FROZEN_AFTER
from nightcrew.supervisor._policy import RestartPolicy
from nightcrew.supervisor._presence import SupervisorPresence
from nightcrew.supervisor._process import DEFAULT_STOP_TIMEOUT, ModuleProcess, ModuleStatus

__all__ = ["Supervisor"]

log = logging.getLogger(__name__)

_DEFAULT_LOG_LINES = 50


class Supervisor:
    """Supervises the modules of ``directory``; nothing starts before :meth:`run`.

    Args:
        directory: Holds the module configurations (see :func:`module_files`).
        socket_path: The control socket.
        log_dir: One rotating log file per module is written here (``<module>.log``).
        log_format: ``text`` or ``json`` (JSON lines) for the modules' log files.
        policy: Makes the restart policy of each module.
        stop_timeout: Seconds a module may take to close before it is killed.
        comm_file: A comm description: the supervisor then joins the bus as a module whose state
            is its heartbeat (see :class:`SupervisorPresence`).
        frozen_after: Wall seconds a module's event loop may go without a heartbeat before its
            process counts as frozen and is killed and restarted (> 0); None: not watched.
    """

    def __init__(
        self,
        directory: Path,
        *,
        socket_path: Path,
        log_dir: Path,
        log_format: str = "text",
        policy: Callable[[], RestartPolicy] = RestartPolicy,
        stop_timeout: float = DEFAULT_STOP_TIMEOUT,
        comm_file: Path | None = None,
        frozen_after: float | None = DEFAULT_FROZEN_AFTER,
    ) -> None:
        if frozen_after is not None and not frozen_after > 0:
            raise SupervisorError(f"frozen_after must be > 0 seconds, got {frozen_after}")
        self._directory = directory
        self._socket_path = socket_path
        self._log_dir = log_dir
        self._log_format = log_format
        self._policy = policy
        self._stop_timeout = stop_timeout
        self._comm_file = comm_file
        self._frozen_after = frozen_after
        self._modules: dict[str, ModuleProcess] = {}

    async def run(self, stop: asyncio.Event | None = None) -> None:
        """Start every module, serve the control socket until ``stop`` or a signal, stop all."""
        stop = stop or asyncio.Event()
        self._log_dir.mkdir(parents=True, exist_ok=True)
        for found in module_files(self._directory):
            self._modules[found.name] = self._make(found)
        presence = SupervisorPresence(self._comm_file, self._statuses) if self._comm_file else None
        control = ControlServer(self._socket_path, self._handle)
        await control.open()
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(sig, stop.set)
        joining: asyncio.Task[None] | None = None
        try:
            log.info("supervising %s; control socket %s", ", ".join(self._modules), self._socket_path)
            for module in self._modules.values():
                module.start()
            if presence is not None:
                # Beside the modules, not before them: its name may be held, which is waited out.
                joining = asyncio.create_task(presence.open())
                joining.add_done_callback(lambda task: _stop_if_failed(task, stop))
            await stop.wait()
            log.info("stopping all modules")
        finally:
            for sig in (signal.SIGINT, signal.SIGTERM):
                loop.remove_signal_handler(sig)
            await control.close()
            for module in reversed(self._modules.values()):
                await module.stop()
            if joining is not None and not joining.done():
                joining.cancel()
                await asyncio.gather(joining, return_exceptions=True)
            if presence is not None:
                await presence.close()
        if joining is not None and _failed(joining):
            raise joining.exception() or RuntimeError  # a login refused: `up` ends with it

    def _statuses(self) -> list[ModuleStatus]:
        return [module.status() for module in self._modules.values()]

    def _make(self, found: Any) -> ModuleProcess:
        return ModuleProcess(
            found,
            log_dir=self._log_dir,
            log_format=self._log_format,
            policy=self._policy(),
            stop_timeout=self._stop_timeout,
            frozen_after=self._frozen_after,
        )

    # --- control requests ----------------------------------------------------------------------

    async def _handle(self, request: dict[str, Any]) -> dict[str, Any]:
        command = request.get("command")
        name = request.get("module")
        if name is not None and not isinstance(name, str):
            raise SupervisorError("module must be a name")
        if command == "status":
            return {"modules": [dataclasses.asdict(m.status()) for m in self._selected(name)]}
        if command in ("start", "restart"):
            self._reread(name)
            for module in self._selected(name):
                if command == "restart":
                    await module.stop()
                module.start()
            return {"modules": [dataclasses.asdict(m.status()) for m in self._selected(name)]}
        if command == "stop":
            for module in reversed(self._selected(name)):
                await module.stop()
            return {"modules": [dataclasses.asdict(m.status()) for m in self._selected(name)]}
        if command == "logs":
            if name is None:
                raise SupervisorError("logs needs a module name")
            lines = request.get("lines", _DEFAULT_LOG_LINES)
            if not isinstance(lines, int) or lines < 1:
                raise SupervisorError("lines must be a positive number")
            return {"lines": _tail(self._selected(name)[0].log_file, lines)}
        raise SupervisorError(f"unknown command {command!r}; known: status, start, stop, restart, logs")

    def _selected(self, name: str | None) -> list[ModuleProcess]:
        if name is None:
            return list(self._modules.values())
        if name not in self._modules:
            raise SupervisorError(f"no module '{name}'; known: {', '.join(self._modules)}")
        return [self._modules[name]]

    def _reread(self, name: str | None) -> None:
        """Before a start by hand: re-read the file(s), so a fixed or newly broken file is seen."""
        for found in module_files(self._directory):
            if name not in (None, found.name):
                continue
            module = self._modules.get(found.name)
            if module is None:
                self._modules[found.name] = self._make(found)
            else:
                module.module = found


def _tail(path: Path, lines: int) -> list[str]:
    try:
        text = path.read_text(errors="replace")
    except FileNotFoundError:
        return []
    return text.splitlines()[-lines:]


def _stop_if_failed(task: asyncio.Task[None], stop: asyncio.Event) -> None:
    if _failed(task):
        stop.set()


def _failed(task: asyncio.Task[None]) -> bool:
    return task.done() and not task.cancelled() and task.exception() is not None
