"""AutonomousWarning: warn people at the telescope while a module may move things on its own.

Every ``interval`` clock seconds it asks every module offering IAutonomous whether it is
autonomous. While one is, it logs a warning (again every ``repeat`` seconds), keeps a flag file
(a VFS path, e.g. read by a dome light) naming the modules, and may run a command (a beep).
"""

from __future__ import annotations

import asyncio
import logging
from typing import Any

from nightcrew.errors import ConfigError
from nightcrew.interfaces import IAutonomous
from nightcrew.interfaces.quantities import Period
from nightcrew.modules.module import Module

__all__ = ["AutonomousWarning"]

log = logging.getLogger(__name__)

#: Wall seconds the warning command may take.
_COMMAND_TIMEOUT = 30.0


class AutonomousWarning(Module):
    """Warns while any module reports ``is_autonomous()``.

    Args:
        interval: Clock seconds between two checks, > 0.
        repeat: Clock seconds between two warnings while it lasts, > 0.
        flag_file: VFS path written (with the modules' names) while autonomous, removed after.
        command: Program and arguments to run with every warning, e.g. ``[aplay, /usr/share/beep.wav]``.
        **kwargs: Module options.
    """

    def __init__(
        self,
        *,
        interval: Period = 10.0,
        repeat: float = 300.0,
        flag_file: str | None = None,
        command: list[str] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(**kwargs)
        for key, value in (("interval", interval), ("repeat", repeat)):
            if not value > 0:
                raise ConfigError(f"must be > 0 seconds, got {value}", key=key)
        if flag_file is not None and not flag_file.startswith("/"):
            raise ConfigError(f"must be an absolute VFS path, got {flag_file!r}", key="flag_file")
        if command is not None and not command:
            raise ConfigError("give the program to run, or leave command out", key="command")
        self._interval, self._repeat = float(interval), float(repeat)
        self._flag_file = flag_file
        self._command = command
        self.autonomous: list[str] = []  # names of the modules acting on their own now
        self._warned_at: float | None = None
        self.add_background_task(self._check_loop)

    async def _check_loop(self) -> None:
        while True:
            await self.check_now()
            await self.clock.sleep(self._interval)

    async def check_now(self) -> None:
        """Ask every IAutonomous module and warn (or stop warning) accordingly."""
        autonomous = []
        for name in await self.comm.clients_with_interface(IAutonomous):
            try:
                if await (await self.proxy(name, IAutonomous)).is_autonomous():
                    autonomous.append(name)
            except Exception as exc:  # one module not answering must not hide the others
                log.debug("%s: asking %s failed: %s", self.name, name, exc)
        await self._update(sorted(autonomous))

    async def _update(self, autonomous: list[str]) -> None:
        now = self.clock.time()
        changed, self.autonomous = autonomous != self.autonomous, autonomous
        if not autonomous:
            if changed:
                log.info("%s: no module is autonomous any more", self.name)
                self._warned_at = None
                if self._flag_file is not None and await self.vfs.exists(self._flag_file):
                    await self.vfs.remove(self._flag_file)
            return
        if changed and self._flag_file is not None:
            await self.vfs.write_bytes(self._flag_file, ("\n".join(autonomous) + "\n").encode())
        if changed or self._warned_at is None or now - self._warned_at >= self._repeat:
            self._warned_at = now
            log.warning("%s: autonomous, may move at any time: %s", self.name, ", ".join(autonomous))
            if self._command:
                await self._run_command()

    async def _run_command(self) -> None:
        assert self._command
        try:
            process = await asyncio.create_subprocess_exec(
                *self._command, stdout=asyncio.subprocess.DEVNULL, stderr=asyncio.subprocess.DEVNULL
            )
            try:
                await asyncio.wait_for(process.wait(), _COMMAND_TIMEOUT)
            except TimeoutError:
                process.kill()
                await process.wait()
                log.warning("%s: warning command took too long and was killed", self.name)
        except OSError as exc:
            log.warning("%s: cannot run warning command %s: %s", self.name, self._command[0], exc)
