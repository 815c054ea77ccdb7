"""Which module a log record belongs to, and forwarding records to the bus as LogEvents.

Several modules may share a process and a logger (``logging.getLogger(__name__)``), so records are
attributed by context: every task a module starts (background tasks, served calls, event handlers)
runs with :data:`current_module` set to that module's name. One :class:`LogForwarder` on the root
logger hands each record of level INFO and up to the sink its module registered.

A sink runs on its module's event loop: a record made in a worker thread (``asyncio.to_thread``
copies the context, and with it the module's name; libraries such as smbprotocol log from there)
is handed over with ``loop.call_soon_threadsafe``, since the sink sends an event and needs the loop.
"""

from __future__ import annotations

import asyncio
import contextlib
import contextvars
import logging
from collections.abc import Callable

__all__ = ["LogForwarder", "current_module", "module_context"]

#: Name of the module the running code works for, if any.
current_module: contextvars.ContextVar[str | None] = contextvars.ContextVar("nightcrew_module", default=None)
#: Set while a record is being forwarded, so that logging inside the forwarding is not forwarded.
_forwarding: contextvars.ContextVar[bool] = contextvars.ContextVar("nightcrew_forwarding", default=False)


def module_context(name: str) -> contextvars.Context:
    """A copy of the current context in which :data:`current_module` is ``name``."""
    context = contextvars.copy_context()
    context.run(current_module.set, name)
    return context


class LogForwarder(logging.Handler):
    """Root-logger handler passing records to the sink of the module they belong to."""

    _instance: LogForwarder | None = None

    def __init__(self) -> None:
        super().__init__(level=logging.INFO)
        #: Module name → its sink and the loop it runs on (None: whatever thread logs).
        self._sinks: dict[
            str, tuple[Callable[[logging.LogRecord], None], asyncio.AbstractEventLoop | None]
        ] = {}

    @classmethod
    def install(cls) -> LogForwarder:
        """The process's forwarder, added to the root logger on first use."""
        if cls._instance is None:
            cls._instance = cls()
            root = logging.getLogger()
            root.addHandler(cls._instance)
            # Records below the root level are never made; INFO ones must be, to be forwarded.
            if root.level > logging.INFO:
                root.setLevel(logging.INFO)
        return cls._instance

    def add_sink(self, module: str, sink: Callable[[logging.LogRecord], None]) -> None:
        """Pass ``module``'s records to ``sink``, on the event loop running now (if any)."""
        self._sinks[module] = (sink, _running_loop())

    def remove_sink(self, module: str) -> None:
        self._sinks.pop(module, None)

    def emit(self, record: logging.LogRecord) -> None:
        if _forwarding.get():
            return
        module = current_module.get()
        entry = self._sinks.get(module) if module else None
        if entry is None:
            return
        sink, loop = entry
        if loop is None or _running_loop() is loop:
            _deliver(sink, record)
        elif not loop.is_closed():
            with contextlib.suppress(RuntimeError):  # the loop closed meanwhile: so is the module's bus
                loop.call_soon_threadsafe(_deliver, sink, record)


def _deliver(sink: Callable[[logging.LogRecord], None], record: logging.LogRecord) -> None:
    token = _forwarding.set(True)
    try:
        sink(record)
    finally:
        _forwarding.reset(token)


def _running_loop() -> asyncio.AbstractEventLoop | None:
    try:
        return asyncio.get_running_loop()
    except RuntimeError:
        return None
