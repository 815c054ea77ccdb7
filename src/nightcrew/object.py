"""The base of everything built from configuration: shared context and supervised tasks.

An :class:`Object` receives the comm, the clock, the observatory site and the virtual file system,
and passes them on to the children it adds. It runs background tasks that are restarted with
backoff when they crash (and logged), all cancelled by one :meth:`close`, which is safe to call
twice. Constructors do no I/O and start nothing; :meth:`open` does.

A VFS belongs to whoever built it. An object that builds its own - from a description (its YAML
``vfs:``), or the empty default - closes it in :meth:`close`, after its tasks and children; one
handed to it ready-made (shared by the modules of a one-process observatory) is left open for
the code that made it to close, after the modules; children share their parent's and never close it.
"""

from __future__ import annotations

import asyncio
import logging
from collections.abc import Callable, Coroutine
from typing import Any, ClassVar, TypeVar

from nightcrew.clock import Clock, RealClock
from nightcrew.comm.base import Comm
from nightcrew.error_limits import ErrorLimit, ErrorLimits, Escalation
from nightcrew.errors import ConfigError, InterfaceError
from nightcrew.interfaces.base import Interface
from nightcrew.interfaces.quantities import TimeZoneName
from nightcrew.log import module_context
from nightcrew.site import Site
from nightcrew.vfs import VirtualFileSystem

__all__ = ["Object"]

log = logging.getLogger(__name__)

T = TypeVar("T")
I = TypeVar("I", bound=Interface)  # noqa: E741 - the conventional name for an interface type

#: Restart delays of a crashed background task grow from ... to ... clock seconds.
_FIRST_RESTART_DELAY = 1.0
_MAX_RESTART_DELAY = 60.0


_WALL_CLOCK = RealClock()


class Object:
    """Base class of modules and of the configurable objects inside them.

    Args:
        comm: The comm to use; a module makes its own when None (see Module).
        clock: Source of time; the wall clock when None.
        vfs: The virtual file system (``{class: nightcrew.vfs.VirtualFileSystem, roots: {...}}``);
            an empty one when None.
        site: Where the observatory stands (``{latitude: .., longitude: .., elevation: ..}``).
        timezone: The observatory's time zone name, e.g. ``Europe/Berlin`` (for display).
    """

    #: Built here, not by the config builder, so that the object owns (and closes) the VFS.
    config_builds_itself: ClassVar[frozenset[str]] = frozenset({"vfs"})

    def __init__(
        self,
        *,
        comm: Comm | dict[str, Any] | None = None,
        clock: Clock | dict[str, Any] | None = None,
        vfs: VirtualFileSystem | dict[str, Any] | None = None,
        site: Site | dict[str, Any] | None = None,
        timezone: TimeZoneName = "UTC",
    ) -> None:
        self._comm: Comm | None = _built(comm, Comm, "comm")
        self._clock: Clock | None = _built(clock, Clock, "clock")
        self._vfs: VirtualFileSystem | None = _built(vfs, VirtualFileSystem, "vfs")
        self._owns_vfs = self._vfs is not None and not isinstance(vfs, VirtualFileSystem)
        self._site: Site | None = _site(site) if isinstance(site, dict) else site
        self.timezone = timezone
        self._children: list[Object] = []
        self._task_factories: list[tuple[str, Callable[[], Coroutine[Any, Any, Any]], bool]] = []
        self._tasks: list[asyncio.Task[Any]] = []
        self._error_limits = ErrorLimits()
        self._is_open = False

    # --- context -------------------------------------------------------------------------------

    @property
    def comm(self) -> Comm:
        if self._comm is None:
            raise ConfigError(f"{type(self).__name__} has no comm (add it to a module as a child)")
        return self._comm

    @property
    def clock(self) -> Clock:
        return self._clock or _WALL_CLOCK

    @property
    def vfs(self) -> VirtualFileSystem:
        if self._vfs is None:
            self._vfs, self._owns_vfs = VirtualFileSystem(), True
        return self._vfs

    @property
    def site(self) -> Site | None:
        return self._site

    @property
    def context_name(self) -> str:
        """Name under which this object's tasks log (the module's name)."""
        return self._comm.name if self._comm is not None else type(self).__name__

    def add_child(self, child: T) -> T:
        """Make ``child`` part of this object: it shares the context and opens/closes with it."""
        if isinstance(child, Object):
            child._comm = child._comm or self._comm
            child._clock = child._clock or self._clock
            child._vfs = child._vfs or self._vfs
            child._site = child._site or self._site
            self._children.append(child)
        return child

    async def proxy(self, target: str | I, interface: type[I]) -> I:
        """A proxy for remote module ``target`` checked for ``interface``; a local object as is.

        This is how a parameter typed ``str | ICamera`` becomes something to call.
        """
        if isinstance(target, interface):
            return target
        if not isinstance(target, str):
            raise InterfaceError(f"{target!r} is neither a module name nor an {interface.__name__}")
        return await self.comm.proxy(target, interface)

    # --- background tasks ----------------------------------------------------------------------

    def add_background_task(
        self, func: Callable[[], Coroutine[Any, Any, Any]], *, restart: bool = True, name: str | None = None
    ) -> None:
        """Run ``func()`` while the object is open; restart it with backoff if it crashes."""
        self._task_factories.append((name or func.__name__, func, restart))
        if self._is_open:
            self._start_task(*self._task_factories[-1])

    def _start_task(self, name: str, func: Callable[[], Coroutine[Any, Any, Any]], restart: bool) -> None:
        task = asyncio.get_running_loop().create_task(
            self._supervise(name, func, restart), name=name, context=module_context(self.context_name)
        )
        self._tasks.append(task)

    async def _supervise(
        self, name: str, func: Callable[[], Coroutine[Any, Any, Any]], restart: bool
    ) -> None:
        delay = _FIRST_RESTART_DELAY
        while True:
            started = self.clock.time()
            try:
                await func()
                return
            except asyncio.CancelledError:
                raise
            except Exception as exc:
                self.handle_exception(exc)
                if not restart:
                    log.exception("background task %s crashed", name)
                    return
                if self.clock.time() - started > _MAX_RESTART_DELAY:
                    delay = _FIRST_RESTART_DELAY  # it ran well for a while: start backoff afresh
                log.exception("background task %s crashed; restarting in %g s", name, delay)
                await self.clock.sleep(delay)
                delay = min(delay * 2, _MAX_RESTART_DELAY)

    # --- errors --------------------------------------------------------------------------------

    def register_exception(
        self,
        error_type: type[BaseException],
        limit: int,
        *,
        timespan: float | None = None,
        module: str | None = None,
        callback: Escalation | None = None,
    ) -> None:
        """Escalate when ``limit`` errors of ``error_type`` (or subclasses) occur.

        Args:
            timespan: Only count errors within this many clock seconds.
            module: Only count errors raised by this remote module.
            callback: Called with the error hitting the limit; default: :meth:`on_error_limit`.
        """
        self._error_limits.register(ErrorLimit(error_type, limit, timespan, module, callback))

    def handle_exception(self, exc: BaseException) -> None:
        """Count ``exc`` against the registered limits and escalate those it hits."""
        for limit in self._error_limits.record(exc, self.clock.time()):
            (limit.callback or self.on_error_limit)(exc)

    def on_error_limit(self, exc: BaseException) -> None:
        """Default escalation; a Module goes to error state."""
        log.error("error limit reached: %s", exc)

    # --- life cycle ----------------------------------------------------------------------------

    async def open(self) -> None:
        """Open children, then start background tasks."""
        if self._is_open:
            return
        for child in self._children:
            await child.open()
        self._is_open = True
        for factory in self._task_factories:
            self._start_task(*factory)

    async def close(self) -> None:
        """Cancel background tasks, close children, then the VFS this object built; safe to call
        twice (the VFS is closed even if the object never opened: it may have been used)."""
        try:
            if not self._is_open:
                return
            self._is_open = False
            tasks, self._tasks = self._tasks, []
            for task in tasks:
                task.cancel()
            await asyncio.gather(*tasks, return_exceptions=True)
            for child in reversed(self._children):
                await child.close()
        finally:
            if self._owns_vfs and self._vfs is not None:
                await self._vfs.close()  # logs a root that fails to close, never raises


def _site(description: dict[str, Any]) -> Site:
    """The site a configuration describes; a bad one is a ConfigError naming the key."""
    try:
        return Site(**description)
    except (TypeError, ValueError) as exc:
        raise ConfigError(str(exc), key="site") from exc


def _built(value: Any, expected: type[T], key: str) -> T | None:
    """``value`` as an object of type ``expected``, building it from a description if needed."""
    if value is None or isinstance(value, expected):
        return value
    if isinstance(value, dict):
        from nightcrew.config import build_object

        try:
            built = build_object(value, expected)
        except ConfigError as exc:  # name the key from the object's own description on
            raise ConfigError(
                exc.message, file=exc.file, line=exc.line, key=f"{key}.{exc.key}" if exc.key else key
            ) from exc
        if not isinstance(built, expected):
            raise ConfigError(f"expected a {expected.__name__}, got {type(built).__name__}", key=key)
        return built
    raise ConfigError(
        f"expected a {expected.__name__} or its description, got {type(value).__name__}", key=key
    )
