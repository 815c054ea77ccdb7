"""Running work under watch: cancel it as soon as a check finds a reason; do several things at once.

These are the mastermind's asyncio mechanics without its comm, so they can be tested alone.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
from collections.abc import Awaitable, Callable, Coroutine, Mapping
from typing import Any

from nightcrew.clock import Clock

__all__ = ["AbortCheck", "all_done", "run_watched"]

log = logging.getLogger(__name__)

#: Says why the work must stop now, or None.
AbortCheck = Callable[[], Awaitable[str | None]]


async def run_watched(
    work: Coroutine[Any, Any, Any],
    check: AbortCheck,
    *,
    wake: asyncio.Event,
    clock: Clock,
    poll_interval: float,
    abort_timeout: float,
    on_abort: Callable[[], Awaitable[None]] | None = None,
) -> str | None:
    """Run ``work``; every ``poll_interval`` clock seconds, and at once when ``wake`` is set, ask ``check``.

    Returns:
        None when the work completed; the cause when ``check`` gave one and the work was cancelled
        (then ``on_abort`` is called, e.g. to abort a remote action; it and the work's clean-up get
        ``abort_timeout`` clock seconds).

    Raises:
        Exception: Whatever the work raised.
        asyncio.CancelledError: The caller was cancelled (the work is cancelled first).
    """
    task: asyncio.Task[Any] = asyncio.ensure_future(work)
    try:
        while True:
            wake.clear()
            woken = asyncio.ensure_future(wake.wait())
            try:
                with contextlib.suppress(TimeoutError):
                    async with clock.timeout(poll_interval):
                        await asyncio.wait({task, woken}, return_when=asyncio.FIRST_COMPLETED)
            finally:
                woken.cancel()
            if task.done():
                if task.cancelled():  # not by us: someone else stopped it
                    return "a cancellation from elsewhere"
                task.result()  # re-raises its error
                return None
            cause = await check()
            if cause is not None:
                log.warning("aborting: %s", cause)
                await _cancel(task, on_abort, clock.to_wall(abort_timeout))
                return cause
    except asyncio.CancelledError:
        await _cancel(task, on_abort, clock.to_wall(abort_timeout))
        raise


async def _cancel(
    task: asyncio.Task[Any], on_abort: Callable[[], Awaitable[None]] | None, wall_timeout: float
) -> None:
    task.cancel()
    steps: list[Awaitable[Any]] = [asyncio.wait({task})]
    if on_abort is not None:
        steps.append(on_abort())
    try:
        async with asyncio.timeout(wall_timeout):
            results = await asyncio.gather(*steps, return_exceptions=True)
    except TimeoutError:
        log.error("the aborted work did not stop within %.0f wall seconds; leaving it", wall_timeout)
        return
    for result in results[1:]:
        if isinstance(result, Exception):
            log.warning("aborting failed: %s", result)
    if not task.cancelled() and task.exception() is not None:
        log.info("the aborted work ended with: %s", task.exception())


async def all_done(actions: Mapping[str, Coroutine[Any, Any, Any]], *, who: str) -> bool:
    """Run ``actions`` (description → coroutine) at once; log each that failed; True if none did."""
    results = await asyncio.gather(*actions.values(), return_exceptions=True)
    ok = True
    for what, result in zip(actions, results, strict=True):
        if isinstance(result, Exception):  # on the way to safety nothing may stop the other actions
            log.error("%s: could not %s: %s", who, what, result or type(result).__name__)
            ok = False
        elif isinstance(result, BaseException):
            raise result
    return ok
