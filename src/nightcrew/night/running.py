"""What every long-running command does alike: quiet module logs, and signals that ask it to stop."""

from __future__ import annotations

import asyncio
import logging
import signal
from collections.abc import AsyncIterator, Iterator
from contextlib import asynccontextmanager, contextmanager

__all__ = ["quiet_module_logs", "stop_on_signals"]


@contextmanager
def quiet_module_logs(show: bool) -> Iterator[None]:
    """Keep the modules' info chatter off stderr unless ``show`` (-v / --debug).

    A command's own output (a progress line, an answer) would be buried under it; warnings and
    errors still show.
    """
    logger = logging.getLogger("nightcrew")
    old_level = logger.level
    if not show:
        logger.setLevel(logging.WARNING)
    try:
        yield
    finally:
        logger.setLevel(old_level)


@asynccontextmanager
async def stop_on_signals(stop: asyncio.Event | None = None) -> AsyncIterator[asyncio.Event]:
    """An event that SIGINT or SIGTERM sets while the block runs (the handlers go afterwards).

    The command then ends the way it always does (park, close) instead of dying mid-way.
    """
    event = stop or asyncio.Event()
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, event.set)
    try:
        yield event
    finally:
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.remove_signal_handler(sig)
