"""Waiting for a condition in tests: polled on a clock, bounded, never a fixed sleep."""

from __future__ import annotations

import inspect
from collections.abc import Awaitable, Callable, Iterable

from nightcrew.clock import Clock, RealClock, VirtualClock
from nightcrew.errors import NightcrewError
from nightcrew.interfaces import IModule, ModuleState
from nightcrew.modules import Module

__all__ = ["Condition", "modules_ready", "wait_for"]

#: Something to wait for: a function returning a bool, or a coroutine function returning one.
Condition = Callable[[], bool | Awaitable[bool]]


async def wait_for(
    condition: Condition,
    clock_seconds: float,
    *,
    clock: Clock | None = None,
    interval: float | None = None,
    message: str = "condition not met",
) -> float:
    """Wait until ``condition()`` holds, at most ``clock_seconds``; return the clock seconds it took.

    The condition is checked at once and then every ``interval`` clock seconds, so a fast clock
    and a real-time device are waited on alike.

    Args:
        condition: Called without arguments; may be a coroutine function (e.g. a status query).
        clock_seconds: How long to wait at most, in seconds of ``clock``.
        clock: Clock of ``clock_seconds`` and ``interval``; the wall clock by default.
        interval: Clock seconds between two checks; by default 1 clock second, or 0.05 wall
            seconds when that is shorter (a slow clock is polled as often as a real device needs;
            a virtual clock costs no wall time to wait on, so 1 clock second).
        message: What was awaited, for the failure message.

    Raises:
        AssertionError: ``condition()`` did not hold within ``clock_seconds``.
    """
    if not clock_seconds >= 0:
        raise ValueError(f"clock_seconds must be >= 0, got {clock_seconds}")
    clock = clock or RealClock()
    step = interval if interval is not None else _default_interval(clock)
    if not step > 0:
        raise ValueError(f"interval must be > 0 clock seconds, got {interval}")
    start = clock.time()
    while not await _holds(condition):
        if clock.time() - start >= clock_seconds:
            raise AssertionError(f"{message}: not within {clock_seconds:g} clock seconds")
        await clock.sleep(step)
    return clock.time() - start


def _default_interval(clock: Clock) -> float:
    return 1.0 if isinstance(clock, VirtualClock) else min(1.0, 0.05 * clock.speed)


async def _holds(condition: Condition) -> bool:
    result = condition()
    if inspect.isawaitable(result):
        result = await result
    return bool(result)


async def modules_ready(caller: Module, names: Iterable[str]) -> bool:
    """Whether every module in ``names`` is on ``caller``'s network and answers that it is ready.

    A condition for :func:`wait_for`. A module joins the network (an XMPP room) before it is ready,
    and until then every call but ``get_state``, ``get_label`` and ``get_version`` fails with
    "module is starting": being among ``caller.comm.clients`` is not enough. A module that leaves
    or restarts while asked is not ready yet.
    """
    online = set(caller.comm.clients)
    for name in names:
        if name not in online:
            return False
        try:
            state = await (await caller.comm.proxy(name, IModule)).get_state()
        except NightcrewError:  # gone again, or the call lost with its connection
            return False
        if ModuleState(state) is not ModuleState.READY:
            return False
    return True
