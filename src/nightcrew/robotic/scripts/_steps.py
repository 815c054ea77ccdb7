"""Running one step of a script: failures named after the step, devices cleaned up when aborted."""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Awaitable, Callable
from typing import Any, TypeVar

from nightcrew.errors import ConfigError, NightcrewError
from nightcrew.robotic.runner import ScriptError

__all__ = ["config_option", "quietly", "step"]

log = logging.getLogger(__name__)

T = TypeVar("T")


async def step(what: str, call: Awaitable[T], *, on_cancel: Callable[[], Awaitable[Any]] | None = None) -> T:
    """Await ``call``, one step of a script described by ``what`` (e.g. "slew to M52").

    Raises:
        ScriptError: The step failed; the message is ``"<what> failed: <cause>"``.
        asyncio.CancelledError: Aborted, after ``on_cancel()`` (its own failure only logged).
    """
    try:
        return await call
    except asyncio.CancelledError:
        if on_cancel is not None:
            await quietly(f"clean up after aborting '{what}'", on_cancel)
        raise
    except ScriptError:
        raise
    except NightcrewError as exc:
        raise ScriptError(f"{what} failed: {type(exc).__name__}: {exc}") from exc


async def quietly(what: str, action: Callable[[], Awaitable[Any]]) -> None:
    """Run a clean-up ``action``; log its failure instead of raising (it must not hide the cause)."""
    try:
        await action()
    except NightcrewError as exc:
        log.error("could not %s: %s", what, exc)


def config_option(key: str, build: Callable[[], T]) -> T:
    """``build()``, its TypeError or ValueError as a ConfigError naming ``key.<first word>``."""
    try:
        return build()
    except (TypeError, ValueError) as exc:
        raise ConfigError(str(exc), key=f"{key}.{str(exc).split()[0]}") from exc
