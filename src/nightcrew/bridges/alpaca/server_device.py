"""One nightcrew module served as one Alpaca device: the members every device type shares.

A device type (telescope, camera, ...) is a subclass of :class:`ServedDevice` whose members are
methods named ``get_<member>`` (answers a GET) and ``put_<member>`` (answers a PUT), each taking the
:class:`~nightcrew.bridges.alpaca.server_protocol.AlpacaRequest` and returning the reply's value.
The served module is reached through a proxy for every request, so a module that restarts, or
lives in another process behind XMPP, is served the same way.

Members a device type does not have are answered with NotImplemented (0x400), as the Alpaca
specification asks for optional members; a member called with the wrong HTTP method is a bad
request. Until a client sets ``Connected`` (or calls ``Connect``), only the common informational
members answer; the others give NotConnected (0x407).

Alpaca's asynchronous operations (SlewToCoordinatesAsync, Move, OpenShutter, ...) start the
nightcrew call in a :class:`BackgroundAction` and return at once; the device reports it as moving
until the call returns. A call that fails in the background is reported with its own error by the
next request that asks whether the device is still moving, so a client learns of it. A second
operation while one runs is refused (InvalidOperation), except those that must always win (Park,
CloseShutter), which the nightcrew module lets preempt the running motion.
"""

from __future__ import annotations

import asyncio
import logging
import re
from collections.abc import Awaitable, Callable, Coroutine
from typing import Any, ClassVar, TypeVar

from nightcrew import __version__
from nightcrew.bridges.alpaca.errors import (
    AlpacaActionNotImplementedError,
    AlpacaNotConnectedError,
)
from nightcrew.bridges.alpaca.members import INFORMATIONAL_MEMBERS, has_method, is_member
from nightcrew.bridges.alpaca.server_protocol import AlpacaRequest, BadRequest
from nightcrew.errors import DeviceBusyError, NightcrewError, NotSupportedError
from nightcrew.interfaces import Interface
from nightcrew.object import Object

__all__ = ["BackgroundAction", "ServedDevice"]

log = logging.getLogger(__name__)

I = TypeVar("I", bound=Interface)  # noqa: E741 - the conventional name for an interface type

_MEMBER = re.compile(r"[a-z][a-z0-9]*")


class BackgroundAction:
    """The one asynchronous operation of a device: runs a nightcrew call while clients poll.

    Args:
        what: The device, for log messages (``telescope 0 (module telescope)``).
    """

    def __init__(self, what: str) -> None:
        self._what = what
        self._task: asyncio.Task[None] | None = None
        self._superseded: set[asyncio.Task[None]] = set()
        self._action = ""
        self._failure: BaseException | None = None

    @property
    def running(self) -> bool:
        """Whether an operation is still under way."""
        return self._task is not None and not self._task.done()

    @property
    def current(self) -> str:
        """The name of the operation under way, empty when none is."""
        return self._action if self.running else ""

    def start(
        self, action: str, call: Callable[[], Coroutine[Any, Any, Any]], *, preempt: bool = False
    ) -> None:
        """Start ``call()`` (a nightcrew call). While one runs, a new one is refused with
        DeviceBusyError unless it ``preempt``s (park, close: the module itself stops the old one,
        whose failure is then not reported)."""
        if self.running and not preempt:
            raise DeviceBusyError(f"{self._what} is busy with {self._action}; wait for it or abort it")
        previous = self._task
        if previous is not None and not previous.done():
            self._superseded.add(previous)
            previous.add_done_callback(self._superseded.discard)
        self._failure = None
        self._action = action
        self._task = asyncio.get_running_loop().create_task(self._run(action, call), name=f"alpaca {action}")

    async def _run(self, action: str, call: Callable[[], Coroutine[Any, Any, Any]]) -> None:
        try:
            await call()
        except asyncio.CancelledError:
            raise
        except Exception as exc:
            if asyncio.current_task() is self._task:  # a superseded operation's end is no news
                log.warning("%s: %s failed: %s", self._what, action, exc)
                self._failure = exc

    async def settle(self, seconds: float) -> None:
        """Wait up to ``seconds`` wall time for the operation, so a refusal reaches the request that
        started it; a slower failure is reported later by :meth:`raise_failure`."""
        if self._task is not None and not self._task.done():
            await asyncio.wait([self._task], timeout=seconds)
        self.raise_failure()

    def raise_failure(self) -> None:
        """Raise (once) the error of an operation that failed."""
        failure, self._failure = self._failure, None
        if failure is not None:
            raise failure

    async def cancel(self) -> None:
        """Forget the operations under way (after the caller stopped the device) and their failures."""
        tasks = [t for t in (self._task, *self._superseded) if t is not None and not t.done()]
        self._task = None
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)
        self._failure = None


class ServedDevice:
    """An Alpaca device backed by a nightcrew module; subclasses add the members of their type.

    Args:
        owner: The server module: its comm reaches ``module``, its VFS, clock and site serve the
            device.
        module: Name of the nightcrew module behind the device.
        number: Alpaca device number (0, 1, ... per device type).
        settle_time: Wall seconds an asynchronous operation may take to be refused before the
            request that started it returns.
    """

    #: Alpaca device type as in URLs (``telescope``) and as in the management API (``Telescope``).
    device_type: ClassVar[str]
    type_name: ClassVar[str]
    #: The Alpaca interface version this server implements for the type.
    interface_version: ClassVar[int]
    #: The nightcrew interface the module must offer.
    interface: ClassVar[type[Interface]]
    #: The operational properties Platform 7's DeviceState reports (as the interface spells them).
    state_members: ClassVar[tuple[str, ...]] = ()

    def __init__(self, owner: Object, module: str, number: int, *, settle_time: float = 0.2) -> None:
        self.owner = owner
        self.module = module
        self.number = number
        self.settle_time = settle_time
        self.connected = False
        self.action = BackgroundAction(self.describe())

    def describe(self) -> str:
        return f"{self.device_type} {self.number} (module {self.module})"

    async def proxy(self, interface: type[I]) -> I:
        """The served module as ``interface`` (raises when it is offline or lacks it)."""
        return await self.owner.proxy(self.module, interface)

    async def optional(self, interface: type[I]) -> I | None:
        """The served module as ``interface`` if it offers it, else None."""
        proxy = await self.owner.comm.proxy(self.module)
        return proxy if isinstance(proxy, interface) else None

    # --- dispatch ------------------------------------------------------------------------------

    async def handle(self, method: str, member: str, request: AlpacaRequest) -> Any:
        """Answer ``method`` (``get`` or ``put``) of ``member``; the reply's value."""
        if not _MEMBER.fullmatch(member) or not is_member(self.device_type, member):
            raise BadRequest(f"{member!r} is not a member of the Alpaca {self.type_name} interface")
        handler = self._handler(method, member)
        if handler is None:
            if not has_method(self.device_type, method, member):
                other = "PUT" if method == "get" else "GET"
                raise BadRequest(f"{self.device_type} member {member} takes {other}, not {method.upper()}")
            raise NotSupportedError(f"{self.device_type} member {member} is not implemented by nightcrew")
        if member not in INFORMATIONAL_MEMBERS and not self.connected:
            raise AlpacaNotConnectedError(
                f"{self.describe()} is not connected; set Connected=true first ({method.upper()} {member})"
            )
        return await handler(request)

    def _handler(self, method: str, member: str) -> Callable[[AlpacaRequest], Awaitable[Any]] | None:
        handler = getattr(self, f"{method}_{member}", None)
        return handler if callable(handler) else None

    # --- members of every device ---------------------------------------------------------------

    async def get_connected(self, request: AlpacaRequest) -> bool:
        return self.connected

    async def put_connected(self, request: AlpacaRequest) -> None:
        connected = request.boolean("Connected")
        if connected:
            await self.proxy(self.interface)  # the module must be online and of the right kind
        self.connected = connected

    async def get_connecting(self, request: AlpacaRequest) -> bool:
        return False  # connecting is immediate: the module is reached through the comm

    async def put_connect(self, request: AlpacaRequest) -> None:
        await self.proxy(self.interface)
        self.connected = True

    async def put_disconnect(self, request: AlpacaRequest) -> None:
        self.connected = False

    async def get_description(self, request: AlpacaRequest) -> str:
        return f"nightcrew module {self.module}"

    async def get_name(self, request: AlpacaRequest) -> str:
        return self.module

    async def get_driverinfo(self, request: AlpacaRequest) -> str:
        return f"nightcrew AlpacaServer serving module {self.module} ({self.interface.__name__})"

    async def get_driverversion(self, request: AlpacaRequest) -> str:
        return __version__

    async def get_interfaceversion(self, request: AlpacaRequest) -> int:
        return self.interface_version

    async def get_supportedactions(self, request: AlpacaRequest) -> list[str]:
        return []

    async def put_action(self, request: AlpacaRequest) -> str:
        action = request.string("Action")
        request.string("Parameters")
        raise AlpacaActionNotImplementedError(
            f"{self.describe()} supports no actions (SupportedActions is empty), not {action!r}"
        )

    async def get_devicestate(self, request: AlpacaRequest) -> list[dict[str, Any]]:
        """Platform 7's DeviceState: the operational properties that can be read right now (one
        that fails, e.g. a temperature the module does not measure, is left out, as the
        specification allows), plus the time they were read."""
        state: list[dict[str, Any]] = []
        for name in self.state_members:
            handler = self._handler("get", name.lower())
            if handler is None:  # a member nightcrew does not implement
                continue
            try:
                state.append({"Name": name, "Value": await handler(request)})
            except NightcrewError:
                continue
        state.append(self.time_stamp())
        return state

    def time_stamp(self) -> dict[str, Any]:
        """DeviceState's TimeStamp entry: the server's clock, UTC, as Alpaca writes dates."""
        return {"Name": "TimeStamp", "Value": self.owner.clock.now().strftime("%Y-%m-%dT%H:%M:%S.%fZ")}
