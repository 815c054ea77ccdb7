"""Virtual time for an asyncio event loop: the engine under :class:`nightcrew.clock.VirtualClock`.

:func:`virtual_time` turns a (running or new) selector event loop into a discrete-event simulator
without replacing it: ``loop.time()`` returns virtual seconds, and when the loop has nothing to do
it jumps to its next timer instead of sleeping. Everything on the loop — ``asyncio.sleep``,
timeouts, ``call_later`` — then runs on virtual time, so an hour of waiting costs no wall time.

The loop counts as busy, and virtual time stands still, while

* a callback is ready (ordinary asyncio work),
* a job submitted through ``loop.run_in_executor`` (``asyncio.to_thread`` too) has not been
  delivered: jobs run in parallel in their threads, but their results are handed to the loop one at
  a time, in the order they were submitted, and only when the loop is otherwise idle — so the order
  in which coroutines resume never depends on which thread finished first;
* a *hold* is taken (:meth:`VirtualTime.hold`): work waiting on the outside world (a plate solver
  in a subprocess) that the loop cannot see as a job.

Only then does time move, straight to the earliest timer. Learnt from the ``looptime`` package
(0.9: a loop whose ``time()`` is fake and whose selector is polled with a zero timeout before the
fake time jumps) and from trio's ``MockClock(autojump_threshold=0)`` (jump when every task is
blocked). looptime itself does not fit: while executor jobs run it moves its time on in wall-time
steps, and thread results reach the loop in the order the threads finish, so a night would still
depend on the machine. Here thread work costs no clock time and its results come in a fixed order.
"""

from __future__ import annotations

import asyncio
import concurrent.futures
import contextlib
import functools
import logging
import selectors
import time as wall
from collections import defaultdict, deque
from collections.abc import Callable, Iterator
from typing import Any

__all__ = ["VirtualTime", "virtual_time"]

log = logging.getLogger(__name__)

#: Wall seconds a hold may wait for the outside world before a warning says the clock is stuck.
HOLD_WARNING_S = 60.0


class VirtualTime:
    """The virtual time of one event loop (made by :func:`virtual_time`)."""

    def __init__(self, loop: asyncio.AbstractEventLoop, origin: float) -> None:
        self.loop = loop
        self.now = origin  # the loop's time(), in virtual seconds
        self._jobs: deque[tuple[concurrent.futures.Future[Any], asyncio.Future[Any], str]] = deque()
        self._holds = 0
        self._executor: concurrent.futures.ThreadPoolExecutor | None = None
        #: Wall seconds the loop stood waiting for thread jobs, by the job's function name, and
        #: (key ``hold``) for the outside world during holds: where a night's wall time goes.
        self.waited: defaultdict[str, float] = defaultdict(float)

    def time(self) -> float:
        return self.now

    @contextlib.contextmanager
    def hold(self) -> Iterator[None]:
        """While inside, virtual time stands still (the loop waits on the outside world instead)."""
        self._holds += 1
        try:
            yield
        finally:
            self._holds -= 1

    @property
    def busy(self) -> bool:
        """Whether a thread job is undelivered or a hold is taken."""
        return bool(self._jobs) or self._holds > 0

    def run_in_executor(
        self, executor: concurrent.futures.Executor | None, func: Callable[..., Any], *args: Any
    ) -> asyncio.Future[Any]:
        if executor is None:
            if self._executor is None:
                self._executor = concurrent.futures.ThreadPoolExecutor(thread_name_prefix="virtual-time")
                self.loop.set_default_executor(self._executor)
            executor = self._executor
        job = executor.submit(func, *args)
        result = self.loop.create_future()
        result.add_done_callback(functools.partial(_cancel_job, job))
        self._jobs.append((job, result, _name_of(func)))
        return result

    def select(self, selector: selectors.BaseSelector, timeout: float | None) -> list[Any]:
        """The loop's selector call: real I/O first, then thread results, then a jump in time."""
        if timeout is not None and timeout <= 0:
            return selector.select(0)
        if self._jobs:  # idle but for threads: hand over the oldest job's result
            self._deliver_oldest()
            return selector.select(0)
        if self._holds:
            began = wall.perf_counter()
            events = selector.select(HOLD_WARNING_S)
            self.waited["hold"] += wall.perf_counter() - began
            if not events:
                log.warning("virtual time held for %.0f wall seconds with nothing arriving", HOLD_WARNING_S)
            return events
        events = selector.select(0)
        if events or timeout is None:  # timeout None: no timer at all, wait for the outside world
            return events or selector.select(None)
        self.now += timeout
        return []

    def _deliver_oldest(self) -> None:
        job, result, name = self._jobs[0]
        began = wall.perf_counter()
        concurrent.futures.wait([job])  # the loop has nothing else to do: block on the thread
        self.waited[name] += wall.perf_counter() - began
        self._jobs.popleft()
        if result.done():  # cancelled by its awaiter meanwhile
            return
        if job.cancelled():
            result.cancel()
        elif (error := job.exception()) is not None:
            result.set_exception(error)
        else:
            result.set_result(job.result())


def _name_of(func: Callable[..., Any]) -> str:
    """``Class.method`` of a job; through the partial that ``asyncio.to_thread`` wraps it in."""
    while isinstance(func, functools.partial):
        func = func.args[0] if func.func.__name__ == "run" and func.args else func.func
    return getattr(func, "__qualname__", type(func).__name__)


def _cancel_job(job: concurrent.futures.Future[Any], result: asyncio.Future[Any]) -> None:
    if result.cancelled():
        job.cancel()  # a job already running finishes in its thread; its result is dropped


class _VirtualSelector(selectors.BaseSelector):
    """The loop's own selector, with :meth:`VirtualTime.select` in front of ``select``."""

    def __init__(self, inner: selectors.BaseSelector, time: VirtualTime) -> None:
        self._inner, self._time = inner, time

    def register(self, fileobj: Any, events: int, data: Any = None) -> selectors.SelectorKey:
        return self._inner.register(fileobj, events, data)

    def unregister(self, fileobj: Any) -> selectors.SelectorKey:
        return self._inner.unregister(fileobj)

    def modify(self, fileobj: Any, events: int, data: Any = None) -> selectors.SelectorKey:
        return self._inner.modify(fileobj, events, data)

    def select(self, timeout: float | None = None) -> list[tuple[selectors.SelectorKey, int]]:
        return self._time.select(self._inner, timeout)

    def close(self) -> None:
        self._inner.close()

    def get_key(self, fileobj: Any) -> selectors.SelectorKey:
        return self._inner.get_key(fileobj)

    def get_map(self) -> Any:
        return self._inner.get_map()


def virtual_time(loop: asyncio.AbstractEventLoop | None = None) -> VirtualTime:
    """The virtual time of ``loop`` (default: the running one), switching it over on first use.

    A loop once switched stays virtual until it is closed.
    """
    loop = loop or asyncio.get_running_loop()
    existing = getattr(loop, "_nightcrew_virtual_time", None)
    if isinstance(existing, VirtualTime):
        return existing
    selector = getattr(loop, "_selector", None)
    if not isinstance(loop, asyncio.SelectorEventLoop) or not isinstance(selector, selectors.BaseSelector):
        raise TypeError(f"virtual time needs a selector event loop, not {type(loop).__name__}")
    # Virtual time starts at 0, not at the loop's (wall) time: clock arithmetic then rounds alike
    # in every run. Timers already set move along, keeping their distance and order.
    shift = loop.time()
    for handle in getattr(loop, "_scheduled", ()):
        handle._when -= shift
    virtual = VirtualTime(loop, 0.0)
    # Instance attributes in front of the class's methods: the loop itself stays what it was.
    loop._selector = _VirtualSelector(selector, virtual)  # type: ignore[attr-defined]
    loop.time = virtual.time  # type: ignore[method-assign]
    loop.run_in_executor = virtual.run_in_executor  # type: ignore[method-assign,assignment]
    loop._nightcrew_virtual_time = virtual  # type: ignore[attr-defined]
    return virtual
