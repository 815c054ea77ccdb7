"""The abstract comm: what every transport offers to modules.

A :class:`Comm` connects one module to the network of modules. Modules only see this class; the
transport (in-process :class:`~nightcrew.comm.local.LocalComm`, XMPP) implements six small hooks
(``_open_transport``, ``_close_transport``, ``_fetch_interface_names``, ``_send_call``,
``_publish_event``, ``_subscribe_events``) plus ``name`` and ``clients``, and reports incoming
traffic through ``_serve_call``, ``_deliver_event`` and ``_client_online``/``_client_offline``.
Everything else — proxies, timeouts, typed errors, event decoding and dispatch — lives here once.

Timeouts: a caller first waits :data:`~nightcrew.timeout.DEFAULT_TIMEOUT` for the callee to announce
the call's timeout, then that long; both in clock seconds, plus ``rpc_grace`` wall seconds for the
network. When it passes, :class:`~nightcrew.errors.RemoteTimeoutError` is raised.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import re
from abc import ABC, abstractmethod
from collections.abc import Awaitable, Callable, Coroutine, Iterator
from contextvars import ContextVar
from typing import Any, ClassVar, TypeVar, overload

from nightcrew.clock import Clock, ClockTimeout, RealClock
from nightcrew.comm.proxy import Proxy, proxy_class
from nightcrew.comm.rpc import CallGuard, ErrorHook, Fault, RpcServer, exception_from_fault
from nightcrew.errors import InterfaceError, ModuleError, NightcrewError, RemoteError, RemoteTimeoutError
from nightcrew.events.base import Event, event_by_name
from nightcrew.interfaces.base import Interface, interface_by_name
from nightcrew.log import current_module, module_context
from nightcrew.security import OPEN_POLICY, AuditLog, Policy, WarningThrottle, closed_policy, load_policy
from nightcrew.timeout import DEFAULT_TIMEOUT

__all__ = ["Comm", "EventHandler", "PendingCall"]

log = logging.getLogger(__name__)

E = TypeVar("E", bound=Event)
I = TypeVar("I", bound=Interface)  # noqa: E741 - the conventional name for an interface type
#: An event handler: ``async def on_x(event, sender) -> None`` (a bool result is ignored).
EventHandler = Callable[[E, str], Awaitable[Any]]

#: The role a module's calls are made in for someone else (see :meth:`Comm.acting_as`).
_acting_as: ContextVar[str | None] = ContextVar("nightcrew_acting_as", default=None)
_IDENTITY = re.compile(r"[A-Za-z0-9_.-]{1,64}")


class PendingCall:
    """A call on its way: the transport reports the announced timeout, the result or a fault."""

    __slots__ = ("_client", "_on_announce", "acting_as", "future", "timeout")

    def __init__(self, client: str, acting_as: str | None = None) -> None:
        self.future: asyncio.Future[Any] = asyncio.get_running_loop().create_future()
        self.timeout: float | None = None
        #: The sub-identity the call is made in (the callee checks ``account:acting_as``), or None.
        self.acting_as = acting_as
        self._client = client
        self._on_announce: Callable[[float], None] | None = None

    def announce(self, timeout: float) -> None:
        """The callee announced that the call may take ``timeout`` clock seconds."""
        self.timeout = timeout
        if self._on_announce is not None:
            self._on_announce(timeout)

    def set_result(self, value: Any) -> None:
        if not self.future.done():
            self.future.set_result(value)

    def set_fault(self, fault: Fault) -> None:
        if not self.future.done():
            self.future.set_exception(exception_from_fault(fault, self._client))

    def set_error(self, error: NightcrewError) -> None:
        """The call failed on the way (e.g. the connection dropped)."""
        if not self.future.done():
            self.future.set_exception(error)


class Comm(ABC):
    """Connects a module to all others: remote calls, proxies, events, presence.

    Args:
        rpc_grace: Wall seconds added to every announced timeout for network latency.
        policy: The observatory's access policy (a YAML file, see :mod:`nightcrew.security`); every
            incoming call is checked against it. ``open``: every caller may call everything. Without
            one, an in-process comm lets every caller call everything, and a network comm
            (:attr:`network`) is closed: nobody may call a state-changing method (see
            :func:`~nightcrew.security.closed_policy`).
        audit: A JSON-lines file where every state-changing call to this module is recorded.
    """

    #: Whether the transport reaches other processes' accounts (XMPP): then closed unless a policy
    #: opens it, and events that move hardware trusted only from the senders a policy names.
    network: ClassVar[bool] = False

    def __init__(
        self, *, rpc_grace: float = 0.0, policy: str | Policy | None = None, audit: str | None = None
    ) -> None:
        self._rpc_grace = rpc_grace
        self._open_policy = policy == OPEN_POLICY
        self._closed_by_default = policy is None and self.network
        self._refusal_warnings = WarningThrottle()  # a forger gets one log line a minute per event
        # Read when built, so that `nightcrew check` reports a broken policy file with its key.
        if isinstance(policy, str):
            self._policy: Policy | None = None if self._open_policy else load_policy(policy)
        else:
            self._policy = closed_policy() if self._closed_by_default else policy
        self._audit = AuditLog(audit) if audit else None
        self._clock: Clock = RealClock()
        self._server: RpcServer | None = None
        self._handlers: dict[str, list[tuple[type[Event], EventHandler[Any]]]] = {}
        self._proxies: dict[str, Proxy] = {}
        self._interface_names: dict[str, list[str]] = {}
        self._tasks: set[asyncio.Task[Any]] = set()
        self._client_waiters: dict[str, list[asyncio.Future[None]]] = {}
        #: Called with every exception a call made through this comm raised (for error limits).
        self.error_hook: ErrorHook | None = None
        #: Called when the transport is lost for good (e.g. another process took over the account);
        #: ``nightcrew run`` then stops with that error, so a supervisor sees the module end.
        self.on_fatal: Callable[[NightcrewError], None] | None = None
        self._is_open = False

    # --- what a transport provides -------------------------------------------------------------

    @property
    @abstractmethod
    def name(self) -> str:
        """Name of the module on this comm."""

    @property
    @abstractmethod
    def clients(self) -> list[str]:
        """Names of the other modules currently online."""

    @abstractmethod
    async def _open_transport(self) -> None: ...

    @abstractmethod
    async def _close_transport(self) -> None: ...

    @abstractmethod
    async def _fetch_interface_names(self, client: str) -> list[str]:
        """Interface names ``client`` advertises; raise RemoteError if it is not online."""

    @abstractmethod
    async def _send_call(self, client: str, method: str, args: list[Any], call: PendingCall) -> None:
        """Send a call; report announcement, result or fault through ``call`` (now or later)."""

    @abstractmethod
    async def _publish_event(self, name: str, payload: dict[str, Any], acting: str | None = None) -> None:
        """Send an event (wire fields) to every other module subscribed to ``name``, sent in the
        identity ``acting`` (see :meth:`acting_as`) if given."""

    @abstractmethod
    async def _subscribe_events(self, name: str) -> None:
        """Start receiving events called ``name``."""

    # --- life cycle ----------------------------------------------------------------------------

    def attach(
        self,
        obj: object,
        *,
        clock: Clock | None = None,
        guard: CallGuard | None = None,
        on_error: ErrorHook | None = None,
    ) -> None:
        """Serve ``obj``'s interface methods on this comm (call before :meth:`open`)."""
        if clock is not None:
            self._clock = clock
        self._server = RpcServer(
            obj,
            guard=guard,
            on_error=on_error,
            name=self.name,
            policy=self._policy,
            audit=self._audit,
            clock=lambda: self._clock,
        )

    @property
    def policy(self) -> Policy | None:
        """The access policy this module's calls are checked against (None: everything allowed)."""
        return self._policy

    @property
    def audit(self) -> AuditLog | None:
        """Where state-changing calls to (and on behalf of people through) this module are recorded."""
        return self._audit

    @property
    def clock(self) -> Clock:
        return self._clock

    async def settle(self) -> None:  # noqa: B027 - optional hook, empty by default
        """Wait (bounded) until :attr:`clients` holds every module that was online when this comm
        opened. A transport that learns of some peers only after ``open()`` (pyobs modules announce
        themselves by presence, then answer discovery) waits for them here."""

    def presence_state(self, client: str) -> str | None:
        """The module state ``client`` shows by presence alone, for peers that cannot be asked
        (pyobs modules have no ``get_state``); None for the others: ask them."""
        return None

    async def wait_for_client(self, name: str, seconds: float) -> bool:
        """Wait up to ``seconds`` (clock seconds, plus the network grace) for module ``name`` to
        come online; whether it is online."""
        if name in self.clients:
            return True
        waiter: asyncio.Future[None] = asyncio.get_running_loop().create_future()
        waiters = self._client_waiters.setdefault(name, [])
        waiters.append(waiter)
        try:
            async with self.timeout(seconds):
                await waiter
        except TimeoutError:
            pass
        finally:
            waiters.remove(waiter)
            if not waiters:
                del self._client_waiters[name]
        return name in self.clients

    def advertise_state(self, state: str) -> None:  # noqa: B027 - optional hook, empty by default
        """Let the others see this module's lifecycle state; transports with presence override it."""

    def timeout(self, seconds: float | None) -> ClockTimeout:
        """``async with comm.timeout(s):`` for something that takes ``s`` clock seconds over this comm:
        the clock's timeout plus the transport's allowance for the network (``rpc_grace`` wall
        seconds, which do not speed up with a simulated clock)."""
        return self._clock.timeout(seconds, grace=self._rpc_grace)

    @property
    def connected(self) -> bool:
        """Whether the transport reaches the others now; a transport that can lose them overrides it."""
        return self._is_open

    def _report_fatal(self, error: NightcrewError) -> None:
        if self.on_fatal is not None:
            self.on_fatal(error)

    @property
    def is_open(self) -> bool:
        """Whether the comm is connected (between :meth:`open` and :meth:`close`)."""
        return self._is_open

    @property
    def served_interfaces(self) -> list[str]:
        """Names of the interfaces this comm serves (empty before :meth:`attach`)."""
        return self._server.interface_names if self._server else []

    def served_interfaces_for(self, caller: str) -> list[str]:
        """The served interfaces announced to account ``caller``: those it may call a method of."""
        return self._server.interfaces_for(caller) if self._server else []

    @staticmethod
    @contextlib.contextmanager
    def acting_as(identity: str) -> Iterator[None]:
        """Make the calls (and send the events) inside ``with comm.acting_as("viewer"):`` in a
        narrower identity.

        A module acting for people (the console's viewers and operators) calls as
        ``account:identity`` (``console:viewer``), which the callee checks against the policy
        like any account: an identity the policy does not list may call nothing. An event sent so
        is trusted as from ``account:identity`` (the policy's ``events``), so a right to send it
        follows the person, not the module. An account can only name sub-identities of itself,
        never another account.
        """
        if not _IDENTITY.fullmatch(identity):
            raise ValueError(f"not an identity name (letters, digits, _ . -): {identity!r}")
        token = _acting_as.set(identity)
        try:
            yield
        finally:
            _acting_as.reset(token)

    async def open(self) -> None:
        """Connect; afterwards others can call this module and see it online."""
        if self._is_open:
            return
        await self._open_transport()
        self._warn_if_unguarded()  # once connected: a failed login stays one line
        self._is_open = True

    async def close(self) -> None:
        """Disconnect and stop all event handlers; safe to call twice."""
        if not self._is_open:
            return
        self._is_open = False
        await self._close_transport()
        for task in list(self._tasks):
            task.cancel()
        await asyncio.gather(*self._tasks, return_exceptions=True)

    def _warn_if_unguarded(self) -> None:
        """At every start, warn when a module on the network is open to everyone; say when it is closed."""
        if not self.network or self._server is None:
            return  # in process, or a client serving nothing (an operator's command)
        if self._open_policy:
            log.warning(
                "%s runs with 'policy: open': every account on the server may call all its methods "
                "(docs/security.md)",
                self.name,
            )
        elif self._closed_by_default:  # safe, so said quietly (people's commands run so, too)
            log.info(
                "%s has no access policy: it refuses every state-changing call (give its comm "
                "'policy: FILE', or 'policy: open'; docs/security.md)",
                self.name,
            )

    # --- discovery and proxies -----------------------------------------------------------------

    async def get_interface_names(self, client: str) -> list[str]:
        """Names of the interfaces ``client`` offers (cached while it stays online)."""
        names = self._interface_names.get(client)
        if names is None:
            names = await self._fetch_interface_names(client)
            self._interface_names[client] = names
        return names

    async def get_interfaces(self, client: str) -> list[type[Interface]]:
        """The interfaces ``client`` offers that this process knows."""
        known = (interface_by_name(n) for n in await self.get_interface_names(client))
        return [i for i in known if i is not None]

    async def clients_with_interface(self, interface: type[Interface]) -> list[str]:
        """Names of the online modules offering ``interface``."""
        found = []
        for client in self.clients:
            try:
                if interface.__name__ in await self.get_interface_names(client):
                    found.append(client)
            except RemoteError:
                continue  # went offline while we asked
        return found

    @overload
    async def proxy(self, name: str, /) -> Proxy: ...

    @overload
    async def proxy(self, name: str, interface: type[I], /, *more: type[Interface]) -> I: ...

    async def proxy(self, name: str, /, *interfaces: type[Interface]) -> Any:
        """A proxy for module ``name``, checked to offer all ``interfaces``; typed as the first.

        Raises:
            RemoteError: ``name`` is not online.
            InterfaceError: it lacks one of ``interfaces``.
        """
        proxy = self._proxies.get(name)
        if proxy is None:
            offered = tuple(await self.get_interfaces(name))
            proxy = proxy_class(offered)(self, name)
            self._proxies[name] = proxy
        missing = [i.__name__ for i in interfaces if not isinstance(proxy, i)]
        if missing:
            offered_names = ", ".join(await self.get_interface_names(name)) or "none"
            raise InterfaceError(
                f"module '{name}' does not offer {', '.join(missing)} (offers: {offered_names})"
            )
        return proxy

    # --- calls ---------------------------------------------------------------------------------

    async def execute(self, client: str, method: str, args: list[Any]) -> Any:
        """Call ``method`` of ``client`` with wire ``args`` and return the wire result.

        Raises the remote exception's class (or RemoteError), or RemoteTimeoutError.
        """
        call = PendingCall(client, _acting_as.get())
        try:
            async with self.timeout(DEFAULT_TIMEOUT) as deadline:
                call._on_announce = deadline.reschedule
                await self._send_call(client, method, args, call)
                return await call.future
        except TimeoutError:
            waited = call.timeout if call.timeout is not None else DEFAULT_TIMEOUT
            error = RemoteTimeoutError(f"{method}() did not finish within {waited:g} s", module=client)
            self._report_error(error)
            raise error from None
        except NightcrewError as exc:
            self._report_error(exc)
            raise

    async def _serve_call(
        self,
        method: str,
        args: list[Any],
        announce: Callable[[float], None],
        caller: str | None = None,
        acting_as: str | None = None,
    ) -> Any:
        """Run an incoming call from account ``caller`` (acting as ``caller:acting_as``, if given)
        on the attached object (for transports)."""
        if caller is not None and acting_as is not None:
            # A malformed identity from the wire becomes one no policy lists: refused everything.
            caller = f"{caller}:{acting_as if _IDENTITY.fullmatch(acting_as) else '?'}"
        if self._server is None:
            raise ModuleError(f"{self.name} serves no methods")
        token = current_module.set(self.name)  # the callee's logs are the callee's
        try:
            return await self._server.handle(method, args, announce, caller)
        finally:
            current_module.reset(token)

    def _report_error(self, exc: BaseException) -> None:
        if self.error_hook is not None:
            self.error_hook(exc)

    # --- events --------------------------------------------------------------------------------

    async def register_event(self, event_type: type[E], handler: EventHandler[E] | None = None) -> None:
        """Receive events of ``event_type`` (from other modules) with ``handler(event, sender)``.

        Without a handler, only announces interest (so senders know someone listens).
        """
        name = event_type.event_name()
        first = name not in self._handlers
        handlers = self._handlers.setdefault(name, [])
        if handler is not None:
            handlers.append((event_type, handler))
        if first:
            await self._subscribe_events(name)

    async def send_event(self, event: Event) -> None:
        """Send ``event`` to every other module that registered for its type."""
        await self._publish_event(event.event_name(), event.to_dict(), _acting_as.get())

    def _deliver_event(
        self, name: str, payload: dict[str, Any], sender: str, acting: str | None = None
    ) -> None:
        """Hand an incoming event (sent in the identity ``acting``, if given) to this module's
        handlers, each in its own task."""
        handlers = self._handlers.get(name)
        if not handlers:
            return
        event_type = event_by_name(name) or handlers[0][0]
        if not self._trusts_event(event_type, payload, sender, acting):
            return
        try:
            event = event_type.from_dict(payload)
        except (NightcrewError, TypeError) as exc:
            log.warning("dropped malformed %s from %s: %s", name, sender, exc)
            return
        for _, handler in handlers:
            self._spawn(self._run_handler(handler, event, sender), f"{name} handler")

    def _trusts_event(
        self, event_type: type[Event], payload: dict[str, Any], sender: str, acting: str | None = None
    ) -> bool:
        """Whether an event from ``sender`` may reach the handlers; a refused one is logged and audited.

        A forged verdict or alarm (a SafetyClearedEvent from an observer) must not move hardware:
        such events are trusted only from the senders the policy names, and without a policy on a
        network transport from nobody (every room member could send them); under an explicit
        `policy: open` from anyone, as the operator chose.
        """
        name, account = event_type.event_name(), self._sender_account(sender)
        if acting is not None:  # as for calls: a malformed identity is one no policy lists
            account = f"{account}:{acting if _IDENTITY.fullmatch(acting) else '?'}"
        if self._policy is None:  # in-process, or `policy: open` (warned at every start)
            return True
        trusted = self._policy.accepts_event(account, name, moves_hardware=event_type.moves_hardware)
        held_back = None if trusted else self._refusal_warnings.due((account, name))
        if held_back is not None:
            log.warning(
                "refused %s from %s: %s%s",
                name,
                account if account == sender else f"{sender} ({account})",
                "the policy does not name it as a sender of this event"
                if not self._closed_by_default
                else "without an access policy, events that move hardware are trusted from nobody on "
                "a network (docs/security.md)",
                f" ({held_back} more refused since the last such line)" if held_back else "",
            )
        if not trusted and self._audit is not None:
            self._audit.record(account, self.name, name, [payload], "forbidden")
        return trusted

    def trusts_headers_from(self, module: str) -> bool:
        """Whether FITS header cards from ``module`` may be used (the policy's ``header_providers``)."""
        return self._policy is None or self._policy.accepts_headers(self._sender_account(module))

    def _sender_account(self, sender: str) -> str:
        """The account behind the module name ``sender`` (transports with nicknames override this)."""
        return sender

    async def _run_handler(self, handler: EventHandler[Any], event: Event, sender: str) -> None:
        try:
            await handler(event, sender)
        except asyncio.CancelledError:
            raise
        except Exception as exc:
            log.exception(
                "handler %s for %s failed", getattr(handler, "__name__", handler), event.event_name()
            )
            self._report_error(exc)

    def _spawn(self, coro: Coroutine[Any, Any, Any], name: str) -> None:
        task = asyncio.get_running_loop().create_task(coro, name=name, context=module_context(self.name))
        self._tasks.add(task)
        task.add_done_callback(self._task_done)

    def _task_done(self, task: asyncio.Task[Any]) -> None:
        # Every background task's outcome is retrieved here: a failure is logged once, never left
        # for asyncio's "exception was never retrieved" at exit (e.g. a discovery cut by close()).
        self._tasks.discard(task)
        if task.cancelled():
            return
        error = task.exception()
        if isinstance(error, NightcrewError):
            log.debug("%s ended: %s", task.get_name(), error)
        elif error is not None:
            log.error("%s failed", task.get_name(), exc_info=error)

    # --- presence ------------------------------------------------------------------------------

    def _client_online(self, client: str) -> None:
        """A module came online (for transports); handlers of ModuleOpenedEvent hear of it."""
        from nightcrew.events import ModuleOpenedEvent

        self._forget(client)
        for waiter in self._client_waiters.get(client, []):
            if not waiter.done():
                waiter.set_result(None)
        self._deliver_event(ModuleOpenedEvent.event_name(), ModuleOpenedEvent().to_dict(), client)

    def _client_offline(self, client: str) -> None:
        """A module went offline (for transports); handlers of ModuleClosedEvent hear of it."""
        from nightcrew.events import ModuleClosedEvent

        self._forget(client)
        self._deliver_event(ModuleClosedEvent.event_name(), ModuleClosedEvent().to_dict(), client)

    def _forget(self, client: str) -> None:
        # Its interfaces may differ when it comes back; existing proxy objects stay usable.
        self._interface_names.pop(client, None)
        self._proxies.pop(client, None)
