"""The base class of all modules.

A module is an :class:`~nightcrew.object.Object` that owns a comm, serves its interfaces' methods
to other modules and has a lifecycle. The lifecycle is data: :data:`TRANSITIONS` lists the allowed
state changes and :meth:`Module._enter` is the only place a state changes.

Run-time configuration (IConfig): a module declares an option ``x`` by defining
``_get_config_x()`` (readable), ``_set_config_x(value)`` (changeable) and optionally
``_get_config_options_x()`` (allowed values); each may be sync or async.
"""

from __future__ import annotations

import inspect
import logging
import typing
from typing import Any

from nightcrew import __version__
from nightcrew.comm.base import Comm
from nightcrew.comm.local import LocalComm
from nightcrew.config import check_value
from nightcrew.errors import ConfigError, InvalidArgumentError, ModuleError
from nightcrew.interfaces import IConfig, IModule, ModuleState
from nightcrew.log import LogForwarder
from nightcrew.object import Object

__all__ = ["TRANSITIONS", "Module"]

log = logging.getLogger(__name__)

#: Allowed state changes; anything else is a bug and raises.
TRANSITIONS: dict[ModuleState, frozenset[ModuleState]] = {
    ModuleState.STARTING: frozenset({ModuleState.READY, ModuleState.ERROR, ModuleState.CLOSING}),
    ModuleState.READY: frozenset({ModuleState.ERROR, ModuleState.CLOSING}),
    ModuleState.ERROR: frozenset({ModuleState.READY, ModuleState.CLOSING}),
    ModuleState.CLOSING: frozenset({ModuleState.CLOSED}),
    ModuleState.CLOSED: frozenset(),
}

#: Methods that answer in every state, starting and closing included: a module is in the room
#: (its presence sent) before it is ready, and asking who and how it is must not race its start.
_ALWAYS_ANSWERED = frozenset({"get_label", "get_version", "get_state"})
#: Methods that still answer while the module is in error state.
_ALLOWED_IN_ERROR = _ALWAYS_ANSWERED | {"get_error_string", "reset_error", "get_config_caps"}
_CONFIG_PREFIXES = ("_get_config_options_", "_get_config_", "_set_config_")


class Module(Object, IModule, IConfig):
    """Base class of all modules.

    Args:
        name: Module name on the network; from the comm when it has one (XMPP: the JID's local
            part), else required (``nightcrew run`` uses the YAML file's name).
        label: Human-readable name; the name by default.
        comm: How to reach other modules; in-process (LocalComm) by default.
    """

    def __init__(
        self,
        *,
        name: str | None = None,
        label: str | None = None,
        comm: Comm | dict[str, Any] | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(comm=comm, **kwargs)
        if self._comm is None:
            if not name:
                raise ConfigError("a module without a comm needs a name", key="name")
            self._comm = LocalComm(name)
        elif name and name != self._comm.name:
            raise ConfigError(f"name '{name}' differs from the comm's name '{self._comm.name}'", key="name")
        self._label = label or self.comm.name
        self._state = ModuleState.STARTING
        self._error_string = ""

    @property
    def name(self) -> str:
        return self.comm.name

    @property
    def state(self) -> ModuleState:
        return self._state

    # --- lifecycle -----------------------------------------------------------------------------

    def _enter(self, state: ModuleState, error: str = "") -> None:
        """The one place where the state changes."""
        old = self._state
        if state not in TRANSITIONS[old]:
            raise ModuleError(f"cannot go from {old} to {state}")
        self._state = state
        self._error_string = error if state is ModuleState.ERROR else ""
        if state is ModuleState.ERROR:
            log.error("%s entered error state: %s", self.name, error)
        else:
            log.debug("%s: %s -> %s", self.name, old, state)
        if self.comm.is_open:
            self.comm.advertise_state(state.value)
            if ModuleState.ERROR in (old, state):  # trouble and its end: people are told (notify)
                self._announce_state(old, state)
        self.on_state_changed(old, state)

    def _announce_state(self, old: ModuleState, new: ModuleState) -> None:
        from nightcrew.events import ModuleStateChangedEvent

        event = ModuleStateChangedEvent(last=old, current=new, error=self._error_string)
        self.comm._spawn(self.comm.send_event(event), "state event")

    def on_state_changed(self, old: ModuleState, new: ModuleState) -> None:
        """Hook for subclasses, called after every state change."""

    async def open(self) -> None:
        """Connect, open children and background tasks, then become READY."""
        if self._state is not ModuleState.STARTING:
            return
        comm = self.comm
        comm.attach(self, clock=self.clock, guard=self._guard_call, on_error=self.handle_exception)
        comm.error_hook = self.handle_exception
        LogForwarder.install().add_sink(self.name, self._forward_log)
        try:
            await comm.open()
            await super().open()
        except BaseException:
            await self.close()
            raise
        self._enter(ModuleState.READY)
        log.info("%s is ready", self.name)

    async def close(self) -> None:
        """Stop tasks, close children and the VFS the module built, then disconnect; safe to call
        twice."""
        if self._state in (ModuleState.CLOSING, ModuleState.CLOSED):
            return
        self._enter(ModuleState.CLOSING)
        try:
            await super().close()
        finally:
            LogForwarder.install().remove_sink(self.name)
            await self.comm.close()
            self._enter(ModuleState.CLOSED)

    def _guard_call(self, method: str) -> None:
        if method in _ALWAYS_ANSWERED:
            return
        if self._state is ModuleState.ERROR and method not in _ALLOWED_IN_ERROR:
            raise ModuleError(f"module is in error state: {self._error_string}")
        if self._state is not ModuleState.READY and self._state is not ModuleState.ERROR:
            raise ModuleError(f"module is {self._state}")

    def set_error(self, message: str) -> None:
        """Go to error state: other modules' calls fail with ModuleError until reset_error()."""
        if self._state is ModuleState.READY:
            self._enter(ModuleState.ERROR, message)

    def on_error_limit(self, exc: BaseException) -> None:
        self.set_error(f"too many {type(exc).__name__}: {exc}")

    # --- log forwarding ------------------------------------------------------------------------

    def _forward_log(self, record: logging.LogRecord) -> None:
        from nightcrew.events import LogEvent

        event = LogEvent(
            time=self.clock.now(),  # clock time: a simulated night's record holds no wall time
            level=record.levelname,
            logger=record.name,
            message=record.getMessage(),
            filename=record.pathname,
            line=record.lineno,
        )
        if self.comm.is_open:
            self.comm._spawn(self.comm.send_event(event), "log forwarding")

    # --- IModule -------------------------------------------------------------------------------

    async def get_label(self) -> str:
        return self._label

    async def get_version(self) -> str:
        return __version__

    async def get_state(self) -> ModuleState:
        return self._state

    async def get_error_string(self) -> str:
        return self._error_string

    async def reset_error(self) -> bool:
        if self._state is ModuleState.ERROR:
            self._error_limits.reset()
            self._enter(ModuleState.READY)
        return self._state is ModuleState.READY

    # --- IConfig -------------------------------------------------------------------------------

    def _config_hook(self, prefix: str, name: str) -> Any:
        return getattr(self, f"{prefix}{name}", None)

    async def get_config_caps(self) -> dict[str, tuple[bool, bool, bool]]:
        names = set()
        for attr in dir(type(self)):
            for prefix in _CONFIG_PREFIXES:
                if attr.startswith(prefix):
                    names.add(attr[len(prefix) :])
                    break
        return {
            name: (
                self._config_hook("_get_config_", name) is not None,
                self._config_hook("_set_config_", name) is not None,
                self._config_hook("_get_config_options_", name) is not None,
            )
            for name in sorted(names)
        }

    async def get_config_value(self, name: str) -> Any:
        return await _call_hook(self._config_hook("_get_config_", name), name, "readable")

    async def set_config_value(self, name: str, value: Any) -> None:
        hook = self._config_hook("_set_config_", name)
        if hook is not None:
            _check_config_value(hook, name, value)
        await _call_hook(hook, name, "changeable", value)
        log.info("config option %s set to %r", name, value)

    async def get_config_value_options(self, name: str) -> list[str]:
        options = await _call_hook(self._config_hook("_get_config_options_", name), name, "a choice")
        return list(options)


def _check_config_value(hook: Any, name: str, value: Any) -> None:
    """Refuse ``value`` unless it fits the hook's type hint and its bounds, as the same key in a
    configuration file would be checked (``Period``, ``Altitude``, ...)."""
    try:
        hints = typing.get_type_hints(hook, include_extras=True)
    except Exception:  # a hint that cannot be evaluated here: the hook checks for itself
        return
    parameters = [key for key in hints if key != "return"]
    if not parameters:
        return
    problem = next(check_value(value, hints[parameters[0]], name, None), None)
    if problem is not None:
        raise InvalidArgumentError(f"config option '{name}': {problem.message}")


async def _call_hook(hook: Any, name: str, what: str, *args: Any) -> Any:
    if hook is None:
        raise InvalidArgumentError(f"config option '{name}' is not {what}")
    result = hook(*args)
    if inspect.isawaitable(result):
        result = await result
    return result
