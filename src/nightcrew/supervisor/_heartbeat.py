"""The heartbeat between a supervised module process and its supervisor, on a pipe of their own.

The supervisor opens a pipe per process and hands its write end to the child (``pass_fds``), naming
it and the interval in the environment (``NIGHTCREW_HEARTBEAT_FD``, ``NIGHTCREW_HEARTBEAT_INTERVAL``).
``nightcrew run`` then writes one byte per interval from a task on its event loop: a loop that
blocks or a process that is stopped (SIGSTOP, a debugger) stops the beat, a busy thread does not
fake it. The supervisor calls a process *frozen* when the beat stops for ``frozen_after`` wall
seconds. Before the first beat the process imports and builds its modules, which may take long on a
busy or small machine: it has ``first_beat_within(frozen_after)`` for that.
"""

from __future__ import annotations

import asyncio
import logging
import os
from collections.abc import Callable
from typing import BinaryIO

__all__ = [
    "DEFAULT_FROZEN_AFTER",
    "FD_VARIABLE",
    "INTERVAL_VARIABLE",
    "beat_interval",
    "first_beat_within",
    "heartbeat_loop",
    "watch_heartbeat",
]

log = logging.getLogger(__name__)

#: Wall seconds without a beat before a process counts as frozen, unless told otherwise.
DEFAULT_FROZEN_AFTER = 30.0
FD_VARIABLE = "NIGHTCREW_HEARTBEAT_FD"
INTERVAL_VARIABLE = "NIGHTCREW_HEARTBEAT_INTERVAL"


def beat_interval(frozen_after: float) -> float:
    """Wall seconds between two beats: four beats may go missing before a process counts as frozen."""
    return min(1.0, frozen_after / 5)


def first_beat_within(frozen_after: float) -> float:
    """Wall seconds from the start to the first beat before a process counts as frozen."""
    return max(120.0, 10 * frozen_after)


async def heartbeat_loop() -> None:
    """In the child: beat on the supervisor's pipe until cancelled; returns at once without one.

    The variables are removed, so that a process this one starts does not write to a pipe it
    does not have.
    """
    fd_text, interval_text = os.environ.pop(FD_VARIABLE, None), os.environ.pop(INTERVAL_VARIABLE, None)
    if fd_text is None or interval_text is None:
        return
    fd, interval = int(fd_text), float(interval_text)
    os.set_blocking(fd, False)  # a full pipe (a supervisor not reading) must not block the loop
    try:
        while True:
            try:
                os.write(fd, b".")
            except BlockingIOError:
                pass
            except OSError as exc:  # the supervisor is gone: nobody to tell
                log.debug("heartbeat pipe closed: %s", exc)
                return
            await asyncio.sleep(interval)
    finally:
        os.close(fd)


async def watch_heartbeat(beats: BinaryIO, frozen_after: float, on_frozen: Callable[[float], None]) -> None:
    """In the supervisor: read ``beats`` (the pipe's read end) until the writer closes it; call
    ``on_frozen(seconds)`` and return when none came for ``frozen_after`` seconds (for
    :func:`first_beat_within` seconds before the first)."""
    loop = asyncio.get_running_loop()
    reader = asyncio.StreamReader()
    transport, _ = await loop.connect_read_pipe(lambda: asyncio.StreamReaderProtocol(reader), beats)
    try:
        timeout = first_beat_within(frozen_after)
        while True:
            try:
                received = await asyncio.wait_for(reader.read(4096), timeout)
            except TimeoutError:
                on_frozen(timeout)
                return
            if not received:
                return  # the process closed the pipe: it ended
            timeout = frozen_after
    finally:
        transport.close()
