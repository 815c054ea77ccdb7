"""What every nightcrew device served over INDI shares: CONNECTION, DRIVER_INFO, actions, states.

A :class:`ServedDevice` wraps a proxy of one nightcrew module and keeps its INDI properties
(:class:`~nightcrew.bridges.indi.server_vectors.Property`). :meth:`ServedDevice.refresh` reads the
module and publishes the properties that changed; :meth:`ServedDevice.request` turns a client's
checked request into a nightcrew call. Calls that take time (a slew, an exposure) run as actions:
the property goes Busy at once, Ok when the call returns and Alert, with the error as its message,
when it fails. Between actions a property follows the device (Busy while it moves, e.g. when the
mastermind slews; Alert in its error state).
"""

from __future__ import annotations

import asyncio
import logging
from abc import ABC, abstractmethod
from collections.abc import Coroutine
from typing import TYPE_CHECKING, Any, ClassVar, Generic, Protocol, TypeVar

from nightcrew import __version__
from nightcrew.bridges.indi.server_vectors import (
    Permission,
    Property,
    PropertyState,
    SwitchMember,
    SwitchRule,
    TextMember,
)
from nightcrew.clock import Clock
from nightcrew.errors import InvalidArgumentError, ModuleError, NightcrewError
from nightcrew.interfaces import Interface

if TYPE_CHECKING:
    from nightcrew.site import Site
    from nightcrew.vfs import VirtualFileSystem

__all__ = ["MAIN_GROUP", "ServedDevice", "ServerLink", "Values", "abort_vector", "switch_on"]

log = logging.getLogger(__name__)

P = TypeVar("P", bound=Interface)
#: A client's request, checked: member name -> number, switch state or text.
Values = dict[str, float | bool | str]
#: The group most clients show first.
MAIN_GROUP = "Main Control"


class ServerLink(Protocol):
    """What a served device needs from the server module."""

    @property
    def clock(self) -> Clock: ...

    @property
    def vfs(self) -> VirtualFileSystem: ...

    @property
    def site(self) -> Site | None: ...

    @property
    def pixel_size(self) -> float:
        """The camera's pixel size in µm as configured (0: unknown until a frame says)."""

    def publish(self, vector: Property[Any]) -> None:
        """Send the vector's current values and state to every client."""

    def publish_blob(self, vector: Property[Any], member: str, data: bytes, fmt: str) -> None:
        """Send ``data`` as ``member`` of the BLOB vector to the clients that enabled BLOBs."""

    def wake(self, device: str) -> None:
        """Refresh ``device`` now rather than at the next poll."""


class ServedDevice(ABC, Generic[P]):
    """One nightcrew module offered to INDI clients as the INDI device ``name``.

    Subclasses say which interface they need (:attr:`interface`), which INDI driver interface bits
    they stand for (:attr:`driver_interface`: 1 telescope, 2 CCD, 8 focuser, 16 filter, 32 dome),
    build their properties in :meth:`_build`, read the device in :meth:`_update` and act in
    :meth:`_request`.
    """

    interface: ClassVar[type[Interface]]
    driver_interface: ClassVar[int]

    def __init__(self, name: str, link: ServerLink) -> None:
        self.name = name
        self._link = link
        self._proxy: P | None = None
        self._actions: dict[str, asyncio.Task[None]] = {}  # the latest action of each property
        self._tasks: set[asyncio.Task[None]] = set()  # every running action, replaced ones too
        self.connection = Property(
            name,
            "CONNECTION",
            "Connection",
            MAIN_GROUP,
            [SwitchMember("CONNECT", "Connect", True), SwitchMember("DISCONNECT", "Disconnect")],
            state=PropertyState.OK,
        )
        self.driver_info = Property(
            name,
            "DRIVER_INFO",
            "Driver Info",
            "General Info",
            [
                TextMember("DRIVER_NAME", "Name", "nightcrew"),
                TextMember("DRIVER_EXEC", "Exec", "nightcrew"),
                TextMember("DRIVER_VERSION", "Version", __version__),
                TextMember("DRIVER_INTERFACE", "Interface", str(self.driver_interface)),
            ],
            perm=Permission.READ_ONLY,
            state=PropertyState.OK,
        )
        #: Every property by name; empty until :meth:`attach`.
        self.vectors: dict[str, Property[Any]] = {}

    @property
    def device(self) -> P:
        if self._proxy is None:
            raise ModuleError(f"INDI device {self.name} is not attached to its module yet")
        return self._proxy

    @property
    def connected(self) -> bool:
        return self.connection.by_name["CONNECT"].on

    async def attach(self, proxy: P) -> None:
        """Take the module's proxy and build the properties from what it offers."""
        self._proxy = proxy
        vectors: list[Property[Any]] = [self.connection, self.driver_info, *await self._build()]
        self.vectors = {v.name: v for v in vectors}

    async def refresh(self) -> None:
        """Read the device and publish every property that changed."""
        before = {name: vector.snapshot() for name, vector in self.vectors.items()}
        try:
            await self._update()
        except NightcrewError as exc:
            if self.connection.state is not PropertyState.ALERT:
                log.warning("INDI device %s cannot read its module: %s", self.name, exc)
                self.connection.message = f"cannot read the nightcrew module: {exc}"
            self.connection.state = PropertyState.ALERT
        else:
            if self.connection.state is PropertyState.ALERT:
                self.connection.state = PropertyState.OK
        for name, vector in self.vectors.items():
            if vector.snapshot() != before[name] or vector.message:
                self._link.publish(vector)

    async def request(self, vector: Property[Any], values: Values) -> None:
        """Act on a client's checked request to ``vector``; raises NightcrewError if refused."""
        if vector is self.connection:
            connect = bool(values.get("CONNECT", False))
            self.connection.by_name["CONNECT"].on = connect
            self.connection.by_name["DISCONNECT"].on = not connect
            self.connection.state = PropertyState.OK if connect else PropertyState.IDLE
            self._link.publish(vector)
            return
        if not self.connected:
            raise InvalidArgumentError(
                f"{self.name} is disconnected; switch {self.name}.CONNECTION.CONNECT On"
            )
        await self._request(vector, values)

    async def close(self) -> None:
        """Cancel running actions (the nightcrew calls they wait for run on in their modules)."""
        tasks = list(self._tasks)
        for task in tasks:
            task.cancel()
        await asyncio.gather(*tasks, return_exceptions=True)

    # --- for subclasses ------------------------------------------------------------------------

    @abstractmethod
    async def _build(self) -> list[Property[Any]]:
        """The device's own properties (CONNECTION and DRIVER_INFO are added)."""

    @abstractmethod
    async def _update(self) -> None:
        """Read the module and set values and states (use :meth:`_follow` for states)."""

    @abstractmethod
    async def _request(self, vector: Property[Any], values: Values) -> None:
        """Act on a request to one of the device's own properties."""

    def acting(self, vector: Property[Any]) -> bool:
        task = self._actions.get(vector.name)
        return task is not None and not task.done()

    def _start(
        self, vector: Property[Any], action: Coroutine[Any, Any, object], *, replace: bool = False
    ) -> None:
        """Run ``action`` for ``vector``: Busy now, then Ok or Alert with the error.

        A second request while the first runs is refused, unless ``replace``: for calls that
        pre-empt the running one in nightcrew (closing a roof, parking), whose outcome then no
        longer counts.
        """
        if self.acting(vector) and not replace:
            action.close()
            raise InvalidArgumentError(f"{vector.where} is busy with the previous request")
        vector.state = PropertyState.BUSY
        self._link.publish(vector)
        task = asyncio.create_task(self._act(vector, action), name=f"INDI {vector.where}")
        self._actions[vector.name] = task
        self._tasks.add(task)
        task.add_done_callback(self._tasks.discard)

    async def _act(self, vector: Property[Any], action: Coroutine[Any, Any, object]) -> None:
        try:
            await action
        except Exception as exc:  # any failure ends in Alert with its reason; the server goes on
            state, message = PropertyState.ALERT, f"{type(exc).__name__}: {exc}"
            if isinstance(exc, NightcrewError):
                log.info("INDI %s failed: %s", vector.where, exc)
            else:
                log.exception("INDI %s failed", vector.where)
        else:
            state, message = PropertyState.OK, ""
        if self._actions.get(vector.name) is not asyncio.current_task():
            return  # replaced by a later request, whose outcome counts
        # Read the values the action left first, so a client that sees Ok reads the new position.
        await self.refresh()
        if self._actions.get(vector.name) is asyncio.current_task():
            vector.state = state
            vector.message = message
            self._link.publish(vector)

    def _follow(self, vector: Property[Any], *, busy: bool, failed: bool = False) -> None:
        """A property's state from the device, unless an action of ours runs on it."""
        if self.acting(vector):
            return
        if busy:
            vector.state = PropertyState.BUSY
        elif failed:
            vector.state = PropertyState.ALERT
        elif vector.state is PropertyState.BUSY:
            vector.state = PropertyState.OK


def abort_vector(device: str, name: str) -> Property[SwitchMember]:
    """A motion's abort switch (``FOCUS_ABORT_MOTION``, ``DOME_ABORT_MOTION``, ...)."""
    vector = Property(device, name, "Abort Motion", MAIN_GROUP, [SwitchMember("ABORT", "Abort")])
    vector.rule = SwitchRule.AT_MOST_ONE
    return vector


def switch_on(vector: Property[SwitchMember], name: str) -> None:
    """SwitchMember member ``name`` on and the others off (OneOfMany properties that show a status)."""
    for member in vector.members:
        member.on = member.name == name
